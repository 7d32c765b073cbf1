/* viscontact_normal.h -- the normal sub-models: hertz, dmt, jkr (pair_coeff: hertz/material E NU,
   dmt E NU W, jkr E NU W; fix viscontact/wall: normal hertz | dmt W | jkr W).

   K. L. Johnson, Contact Mechanics, CUP 1985, ch. 4 and 5; Johnson, Kendall, Roberts, Proc. R.
   Soc. A 324 (1971) 301; Derjaguin, Muller, Toporov, J. Colloid Interface Sci. 53 (1975) 314.
   k = (4/3) E*, k_H = k sqrt(R*):
     hertz  a = sqrt(R* delta), F_ne = k a delta,                       F0 = |F_n|
     dmt    a = sqrt(R* delta), F_ne = k a delta - 4 pi W R*,           F0 = |F_ne + 8 pi W R*|
     jkr    delta = a^2/R* - 2 sqrt(pi W a / E*), F_ne = k a^3/R* - 4 sqrt(pi W E*) a^(3/2),
            F0 = |F_ne + 6 pi W R*|; the contact forms at delta > 0 and lives until
            delta < -delta_c, delta_c = (3 pi^2/16)^(1/3) (R* W^2/E*^2)^(1/3).
   The damping sees delta_a = a^2/R* (= delta for hertz, dmt).  Elastic energy U(delta) =
   int F_ne d(delta): hertz (2/5) k_H delta^(5/2), dmt minus F_po delta, jkr from -delta_c.
   W (native's cohesion) is mixed as the geometric mean.  No history.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_NORMAL_H
#define VISCONTACT_NORMAL_H

#include "viscontact_submodel.h"

namespace viscontact {

/// JKR contact radius on the stable branch for overlap delta (the closed-form root of
/// delta = a^2/R - 2 sqrt(pi W a/E*), as LAMMPS granular's), dR = delta R*.
inline double jkr_contact_radius(double reff, double delta, double W, double Estar)
{
  const double dR = delta * reff;
  const double R2 = reff * reff, dR2 = dR * dR;
  const double t0 = W * W * R2 * R2 * Estar;
  const double t1 = 27.0 * PI * PI * t0;
  const double t2 = 8.0 * dR * dR2 * Estar * Estar * Estar;
  const double t3 = 4.0 * dR2 * Estar;
  const double s1 = t0 * (t1 + 2.0 * t2);
  const double t4 = std::cbrt(t1 + t2 + 3.0 * std::sqrt(3.0) * PI * std::sqrt(s1 > 0.0 ? s1 : 0.0));
  const double t5 = t3 / t4 + t4 / Estar;
  const double s2 = 2.0 * dR + t5;
  const double t6 = std::sqrt(s2 > 0.0 ? s2 : 0.0);
  const double s3 = 4.0 * dR - t5 + 6.0 * std::sqrt(6.0) * W * PI * R2 / (Estar * t6);
  return (t6 + std::sqrt(s3 > 0.0 ? s3 : 0.0)) / std::sqrt(6.0);
}

/// JKR pull-off overlap delta_c = (3 pi^2/16)^(1/3) (R* W^2/E*^2)^(1/3) (> 0) [length].
inline double jkr_pulloff_distance(double reff, double W, double Estar)
{
  if (reff <= 0.0 || W <= 0.0) return 0.0;
  return 1.2277228507842888 * std::cbrt(reff * W * W / (Estar * Estar));
}

/// G(a) = int F_ne d(delta) along the JKR branch up to contact radius a (without constant):
/// (8E*/(15R*^2)) a^5 - (8/(3R*)) sqrt(pi W E*) a^(7/2) + 2 pi W a^2.
inline double jkr_energy_primitive(double a, double reff, double W, double Estar)
{
  return 8.0 * Estar / (15.0 * reff * reff) * a * a * a * a * a -
      8.0 / (3.0 * reff) * std::sqrt(PI * W * Estar) * a * a * a * std::sqrt(a) +
      2.0 * PI * W * a * a;
}

/// What the normal models share: the contact ends at zero overlap, F0 = |F_n|.
template <class Derived> struct NormalBase {
  static double pulloff_distance(double, double) { return 0.0; }
  void critical_force(ContactState &s) const { s.F0 = std::fabs(s.fn); }
};

/// Hertz without cohesion: F_ne = (4/3) E* a delta.
struct NormalHertz : NoValues<NormalHertz>, NormalBase<NormalHertz> {
  static constexpr const char *NAME = "hertz";
  static constexpr const char *PAIR_NAME = "hertz/material";
  static constexpr bool COHESIVE = false;
  static void flip(double *) {}
  std::string parse_W(const std::string &, const std::string &) { return ""; }

  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s) const
  {
    const double dpos = s.delta > 0.0 ? s.delta : 0.0;
    s.a = std::sqrt(s.reff * dpos);
    s.fne = 4.0 / 3.0 * s.Estar * s.a * dpos;
    s.U = 0.4 * s.fne * dpos;
    s.delta_a = dpos;
  }
};

/// A cohesive model's surface energy W [energy/length^2] (native's cohesion): its parsing,
/// mixing and record.
template <class Derived> struct Cohesion : NormalBase<Derived> {
  static constexpr int VERSION = 1;
  double W = 0.0;
  int history_size() const { return 0; }
  static void flip(double *) {}
  static constexpr bool COHESIVE = true;
  static std::string usage() { return "W"; }
  /// W from text; the message names it `label`.
  std::string parse_W(const std::string &label, const std::string &text)
  {
    return parse_number(label, text, PHYSICAL_DOMAIN, W);
  }
  std::string parse(const Args &args, size_t &i)
  {
    if (i >= args.size()) return std::string("normal ") + Derived::NAME + " needs W";
    return parse_W(std::string("normal ") + Derived::NAME + " W", args[i++]);
  }
  static Derived mix(const Derived &a, const Derived &b)
  {
    Derived m = a;
    m.W = detail::geo(a.W, b.W);
    return m;
  }
  std::vector<double> coefficients() const { return {W}; }
  std::string from_coefficients(const std::vector<double> &v)
  {
    std::string err = check_count(Derived::NAME, v, 1);
    if (err.empty()) W = v[0];
    return err;
  }
  void critical_force(ContactState &s) const { s.F0 = std::fabs(s.fne + 2.0 * s.fpo); }
};

/// DMT: Hertz minus the constant pull-off force 4 pi W R*.
struct NormalDMT : Cohesion<NormalDMT> {
  static constexpr const char *NAME = "dmt";
  static constexpr const char *PAIR_NAME = "dmt";

  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s) const
  {
    const double dpos = s.delta > 0.0 ? s.delta : 0.0;
    s.a = std::sqrt(s.reff * dpos);
    s.fne = 4.0 / 3.0 * s.Estar * s.a * dpos;
    s.U = 0.4 * s.fne * dpos;
    s.fpo = 4.0 * PI * W * s.reff;
    s.fne -= s.fpo;
    s.U -= s.fpo * dpos;
    s.delta_a = dpos;
    s.cohesive = true;
  }
};

/// JKR: the contact radius of the JKR branch; the contact lives on to the pull-off distance.
struct NormalJKR : Cohesion<NormalJKR> {
  static constexpr const char *NAME = "jkr";
  static constexpr const char *PAIR_NAME = "jkr";

  double pulloff_distance(double reff, double Estar) const
  {
    return jkr_pulloff_distance(reff, W, Estar);
  }

  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s) const
  {
    const double E = s.Estar, reff = s.reff;
    s.a = jkr_contact_radius(reff, s.delta, W, E);
    const double a = s.a, a2 = a * a;
    s.fne = 4.0 / 3.0 * E * a * a2 / reff - 2.0 * PI * a2 * std::sqrt(4.0 * W * E / (PI * a));
    s.fpo = 3.0 * PI * W * reff;
    s.delta_a = a2 / reff;
    if (s.energy) {
      const double ac = std::cbrt(9.0 * PI * W * reff * reff / (4.0 * E));
      s.U = jkr_energy_primitive(a, reff, W, E) - jkr_energy_primitive(ac, reff, W, E);
    }
    s.cohesive = true;
  }
};

/// The normal models (the registration: one line per model).
using NormalModel = std::variant<NormalHertz, NormalDMT, NormalJKR>;

/// The NORMAL model of a pair_coeff line starting at args[i]: `hertz/material E NU`,
/// `dmt E NU W` or `jkr E NU W`; advances i past it.  Returns an error message, or "".
inline std::string parse_pair_normal(const Args &args, size_t &i, NormalModel &normal, double &E,
                                     double &nu)
{
  const std::string model = i < args.size() ? args[i] : "";
  std::string err;
  std::vector<std::string> forms;
  bool found = false;
  auto try_one = [&](auto *tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    forms.push_back(quoted(std::string(T::PAIR_NAME) + " E NU" + (T::COHESIVE ? " W" : "")));
    if (found || model != T::PAIR_NAME) return;
    found = true;
    const size_t nval = T::COHESIVE ? 3 : 2;
    if (i + nval >= args.size()) {
      err = model + (T::COHESIVE ? " needs three values, E NU W" : " needs two values, E and NU");
      return;
    }
    err = parse_material("E", "nu", args[i + 1], args[i + 2], E, nu);
    if (!err.empty()) err += native_hint(args, i);    // native's E DAMP NU
    T &t = normal.emplace<T>();
    if (err.empty() && T::COHESIVE) err = t.parse_W(model + " W", args[i + 3]);
    i += nval + 1;
  };
  try_one(static_cast<NormalHertz *>(nullptr));
  try_one(static_cast<NormalDMT *>(nullptr));
  try_one(static_cast<NormalJKR *>(nullptr));
  if (!found)
    return "expected " + join_alternatives(forms) + " after the two types, got " + quoted(model) +
        native_hint(args, i);
  return err;
}

/// The wall's `normal hertz | dmt W | jkr W` at args[i] (the keyword itself); advances i.
inline std::string parse_wall_normal(const Args &args, size_t &i, NormalModel &normal)
{
  const std::string model = i + 1 < args.size() ? args[i + 1] : "";
  const size_t at = i + 1;
  i += 2;
  std::string err;
  if (parse_alternative(normal, model, args, i, err)) return err;
  return "normal must be followed by " +
      join_alternatives(alternative_usages(static_cast<NormalModel *>(nullptr))) + ", got " +
      quoted(model) + native_hint(args, at);
}

}    // namespace viscontact

#endif
