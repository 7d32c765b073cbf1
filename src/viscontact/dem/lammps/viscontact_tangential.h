/* viscontact_tangential.h -- the tangential sub-models, as LAMMPS pair granular's:

       tangential none | linear_nohistory XGAMMA MU | linear_history KT XGAMMA MU
                | mindlin KT|NULL XGAMMA MU | mindlin MU (= mindlin NULL 0 MU)
                | mindlin_rescale | mindlin/force | mindlin_rescale/force  KT|NULL XGAMMA MU

   Tangential damping eta_t = XGAMMA eta_n (the normal prefactor before the clamp), Coulomb
   limit |F_t| <= MU F0.  Springs (Mindlin 1949; Cundall & Strack 1979): the displacement xi
   (or, for the /force forms, the elastic force) kept per contact, turned into the current
   tangent plane each step with its length kept (Luding, Granular Matter 10 (2008) 235), xi +=
   v_tr dt, F_t = -k_t xi - eta_t v_tr, capped at MU F0 with xi rewritten to match (native's
   rule: the dashpot stays whole).  k_t = KT (linear_history, force/length) or KT a (mindlin,
   force/length^2; NULL: 8 G* a).  The rescale forms scale xi by a/a_last when the contact
   shrinks.  History: xi (3, negated when i and j swap) and, for the rescale forms, the last
   contact radius.  Mixing: KT, XGAMMA, MU geometric means (NULL if either type has NULL).
   Spring energy (1/2) k_t |xi|^2 (|h|^2 / (2 k_t) for the force forms).

   A new model: one type below (NAME, usage, parse, mix, history_size/flip, record,
   calculate) and one line in TangentialModel.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_TANGENTIAL_H
#define VISCONTACT_TANGENTIAL_H

#include "viscontact_submodel.h"

namespace viscontact {

/// No tangential force.
struct TangentialNone : NoValues<TangentialNone> {
  static constexpr const char *NAME = "none";
  int history_size() const { return 0; }
  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *) const
  {
    s.eta_t = 0.0 * s.eta_n;
  }
};

/// A dashpot capped by Coulomb's limit, no spring: F_t = -min(eta_t |v_tr|, MU F0) v_tr/|v_tr|.
struct TangentialLinearNoHistory {
  static constexpr const char *NAME = "linear_nohistory";
  static constexpr int VERSION = 1;
  double xgamma = 0.0, mu = 0.0;

  static std::string usage() { return "XGAMMA MU"; }
  std::string parse(const Args &args, size_t &i)
  {
    if (i + 1 >= args.size()) return "tangential linear_nohistory needs XGAMMA MU";
    i += 2;
    return parse_numbers(args, i - 2, "tangential linear_nohistory ", {"XGAMMA", "MU"},
                         {&PHYSICAL_DOMAIN, &MU_DOMAIN}, {&xgamma, &mu});
  }
  static TangentialLinearNoHistory mix(const TangentialLinearNoHistory &a,
                                       const TangentialLinearNoHistory &b)
  {
    return {detail::geo(a.xgamma, b.xgamma), detail::geo(a.mu, b.mu)};
  }
  int history_size() const { return 0; }
  static void flip(double *) {}
  std::vector<double> coefficients() const { return {xgamma, mu}; }
  std::string from_coefficients(const std::vector<double> &v)
  {
    std::string err = check_count(NAME, v, 2);
    if (err.empty()) xgamma = v[0], mu = v[1];
    return err;
  }

  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *) const
  {
    s.eta_t = xgamma * s.eta_n;
    const double fscrit = mu * s.F0;
    const double vrel = std::sqrt(detail::dot3(s.vtr, s.vtr));
    if (vrel != 0.0) {
      const double fmag = s.eta_t * vrel;
      const double f = (fmag < fscrit ? fmag : fscrit) / vrel;
      for (int k = 0; k < 3; k++) s.ft[k] = -f * s.vtr[k];
      for (int k = 0; k < 3; k++) s.fdamp_t[k] = s.ft[k];
    }
  }
};

/// A spring with history: linear_history (MINDLIN false) or the mindlin family (k_t = k a,
/// RESCALE: xi follows a shrinking contact, FORCE: the history is the elastic force).
template <bool MINDLIN, bool RESCALE, bool FORCE> struct TangentialSpring {
  static constexpr const char *NAME = !MINDLIN ? "linear_history"
      : RESCALE ? (FORCE ? "mindlin_rescale/force" : "mindlin_rescale")
                : (FORCE ? "mindlin/force" : "mindlin");
  static constexpr int VERSION = 1;
  double kt = 0.0;         ///< KT (linear_history: force/length; mindlin: force/length^2)
  bool kt_null = false;    ///< mindlin: KT given as NULL (k = 8 G*)
  double xgamma = 0.0, mu = 0.0;

  static std::string usage() { return MINDLIN ? "KT|NULL XGAMMA MU" : "KT XGAMMA MU"; }
  std::string parse(const Args &args, size_t &i)
  {
    const std::string pre = std::string("tangential ") + NAME + " ";
    if (!MINDLIN) {
      if (i + 2 >= args.size()) return pre + "needs KT XGAMMA MU";
      i += 3;
      return parse_numbers(args, i - 3, pre, {"KT", "XGAMMA", "MU"},
                           {&PHYSICAL_DOMAIN, &PHYSICAL_DOMAIN, &MU_DOMAIN}, {&kt, &xgamma, &mu});
    }
    const bool long_form = i + 2 < args.size() && (args[i] == "NULL" || is_number(args[i])) &&
        is_number(args[i + 1]) && is_number(args[i + 2]);
    if (!RESCALE && !FORCE && !long_form) {
      // the short form `mindlin MU` = `mindlin NULL 0 MU`
      if (i >= args.size()) return pre + "needs MU (in [0, 10]) or KT|NULL XGAMMA MU";
      kt_null = true;
      xgamma = 0.0;
      return parse_number(pre + "MU", args[i++], MU_DOMAIN, mu);
    }
    if (!long_form) return pre + "needs KT|NULL XGAMMA MU (three numbers)";
    kt_null = args[i] == "NULL";
    std::string err = kt_null ? "" : parse_number(pre + "KT", args[i], PHYSICAL_DOMAIN, kt);
    i += 3;
    if (!err.empty()) return err;
    return parse_numbers(args, i - 2, pre, {"XGAMMA", "MU"}, {&PHYSICAL_DOMAIN, &MU_DOMAIN},
                         {&xgamma, &mu});
  }
  static TangentialSpring mix(const TangentialSpring &a, const TangentialSpring &b)
  {
    TangentialSpring m;
    m.kt_null = a.kt_null || b.kt_null;
    m.kt = m.kt_null ? 0.0 : detail::geo(a.kt, b.kt);
    m.xgamma = detail::geo(a.xgamma, b.xgamma);
    m.mu = detail::geo(a.mu, b.mu);
    return m;
  }
  /// xi (3), and the last contact radius for the rescale forms.
  int history_size() const { return RESCALE ? 4 : 3; }
  static void flip(double *sign)
  {
    // seen from j, n and v_t flip, so xi does
    for (int k = 0; k < 3; k++) sign[k] = -1.0;
  }
  std::vector<double> coefficients() const { return {kt, kt_null ? 1.0 : 0.0, xgamma, mu}; }
  std::string from_coefficients(const std::vector<double> &v)
  {
    std::string err = check_count(NAME, v, 4);
    if (err.empty()) kt = v[0], kt_null = v[1] != 0.0, xgamma = v[2], mu = v[3];
    return err;
  }

  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *h) const
  {
    using detail::dot3;
    s.k_t = kt_null ? 8.0 * s.Gstar : kt;    // also twisting marshall's
    s.eta_t = xgamma * s.eta_n;
    s.mu_t = mu;
    const double fscrit = mu * s.F0;
    double *xi = h;
    const double k = MINDLIN ? s.k_t * s.a : kt;
    if (RESCALE && s.a < h[3]) {
      const double f = s.a / h[3];
      for (int q = 0; q < 3; q++) xi[q] *= f;
    }
    if (s.advance) {
      const double rsht = std::fabs(dot3(xi, s.n));
      if ((FORCE ? rsht : rsht * k) > 1e-10 * fscrit) detail::rotate_rescale(xi, s.n);
      for (int q = 0; q < 3; q++) xi[q] += FORCE ? -k * s.dt * s.vtr[q] : s.dt * s.vtr[q];
      if (RESCALE) h[3] = s.a;
    }
    double fdmp[3];
    for (int q = 0; q < 3; q++) {
      fdmp[q] = -s.eta_t * s.vtr[q];
      s.ft[q] = (FORCE ? xi[q] : -k * xi[q]) + fdmp[q];
    }
    for (int q = 0; q < 3; q++) s.fdamp_t[q] = fdmp[q];
    const double magfs = std::sqrt(dot3(s.ft, s.ft));
    if (magfs > fscrit) {
      if (dot3(xi, xi) != 0.0) {
        const double f = fscrit / magfs;
        const double back = FORCE ? 1.0 : -1.0 / k;
        for (int q = 0; q < 3; q++) {
          s.ft[q] *= f;
          xi[q] = (s.ft[q] - fdmp[q]) * back;
        }
        // the capped force is the rescaled spring plus the whole dashpot (native's rewrite of
        // xi), so the whole dashpot still works: sliding is the rest of the force's work
      } else {
        s.ft[0] = s.ft[1] = s.ft[2] = 0.0;
        s.fdamp_t[0] = s.fdamp_t[1] = s.fdamp_t[2] = 0.0;
      }
    }
    if (s.energy)
      s.el_t = FORCE ? (k > 0.0 ? 0.5 * dot3(xi, xi) / k : 0.0) : 0.5 * k * dot3(xi, xi);
  }
};

using TangentialLinearHistory = TangentialSpring<false, false, false>;
using TangentialMindlin = TangentialSpring<true, false, false>;
using TangentialMindlinRescale = TangentialSpring<true, true, false>;
using TangentialMindlinForce = TangentialSpring<true, false, true>;
using TangentialMindlinRescaleForce = TangentialSpring<true, true, true>;

/// The tangential models (the registration: one line per model).
using TangentialModel =
    std::variant<TangentialNone, TangentialLinearNoHistory, TangentialLinearHistory,
                 TangentialMindlin, TangentialMindlinRescale, TangentialMindlinForce,
                 TangentialMindlinRescaleForce>;

/// Twisting marshall needs a spring (linear_history or a mindlin model).
inline bool has_spring(const TangentialModel &t)
{
  return !std::holds_alternative<TangentialNone>(t) &&
      !std::holds_alternative<TangentialLinearNoHistory>(t);
}

}    // namespace viscontact

#endif
