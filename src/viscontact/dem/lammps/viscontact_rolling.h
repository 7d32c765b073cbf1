/* viscontact_rolling.h -- the rolling sub-models: none, or `rolling sds KR GAMMAR MUR`
   (spring-dashpot-slider, Luding, Granular Matter 10 (2008) 235; Wang et al. 2015; LAMMPS pair
   granular's `rolling sds`): the rolling displacement xi_R (3, kept per contact, turned into
   the tangent plane each step) grows by v_R dt, v_R = R* (w_i - w_j) x n; F_R = -KR xi_R -
   GAMMAR v_R, capped at MUR F0 (xi_R rewritten to match); torque R* n x F_R on i, minus that
   on j.  Mixing: geometric means.  History: xi_R (3; seen from j it keeps its sign: both
   factors of v_R flip).  Spring energy (1/2) KR |xi_R|^2.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_ROLLING_H
#define VISCONTACT_ROLLING_H

#include "viscontact_submodel.h"

namespace viscontact {

/// No rolling resistance (not a keyword: the default).
struct RollingNone : NoValues<RollingNone>, Absent {
  static constexpr const char *NAME = "none";
  int history_size() const { return 0; }
  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &, double *, ContactResult &) const {}
};

/// `WHAT sds K GAMMA MU` values at args[i] (rolling or twisting; names: the three values'
/// names in the messages): K > 0, GAMMA >= 0, MU in mu_domain; advances i past them.
inline std::string parse_sds(const Args &args, size_t &i, const std::string &what,
                             const char *const names[3], const Domain &mu_domain, double &k,
                             double &gamma, double &mu)
{
  const std::string head = what + " sds ";
  if (i + 2 >= args.size()) return head + "needs " + names[0] + " " + names[1] + " " + names[2];
  i += 3;
  return parse_numbers(args, i - 3, head, {names[0], names[1], names[2]},
                       {&POSITIVE_DOMAIN, &PHYSICAL_DOMAIN, &mu_domain}, {&k, &gamma, &mu});
}

/// Spring, dashpot and slider of a rolling or twisting sds model: K, GAMMA, MU.
template <class Derived> struct SDSValues {
  static constexpr int VERSION = 1;
  double k = 0.0, gamma = 0.0, mu = 0.0;
  static Derived mix(const Derived &a, const Derived &b)
  {
    Derived m;
    m.k = detail::geo(a.k, b.k);
    m.gamma = detail::geo(a.gamma, b.gamma);
    m.mu = detail::geo(a.mu, b.mu);
    return m;
  }
  std::vector<double> coefficients() const { return {k, gamma, mu}; }
  std::string from_coefficients(const std::vector<double> &v)
  {
    std::string err = check_count(Derived::NAME, v, 3);
    if (err.empty()) k = v[0], gamma = v[1], mu = v[2];
    return err;
  }
};

struct RollingSDS : SDSValues<RollingSDS> {
  static constexpr const char *NAME = "sds";
  static std::string usage() { return "KR GAMMAR MUR"; }
  std::string parse(const Args &args, size_t &i)
  {
    static const char *const names[3] = {"KR", "GAMMAR", "MUR"};
    return parse_sds(args, i, "rolling", names, MU_DOMAIN, k, gamma, mu);
  }
  int history_size() const { return 3; }
  static void flip(double *) {}

  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *h, ContactResult &res) const
  {
    using detail::dot3;
    double vrl[3];
    detail::cross3(s.relrot, s.n, vrl);
    for (int q = 0; q < 3; q++) vrl[q] *= s.reff;
    double xr[3] = {h[0], h[1], h[2]};
    double *fr = s.fr;
    const double frcrit = mu * s.F0;
    if (s.advance && std::fabs(dot3(xr, s.n)) * k > 1e-10 * frcrit) detail::rotate_rescale(xr, s.n);
    if (s.advance) for (int q = 0; q < 3; q++) xr[q] += s.dt * vrl[q];
    for (int q = 0; q < 3; q++) fr[q] = -k * xr[q] - gamma * vrl[q];
    const double magfr = std::sqrt(dot3(fr, fr));
    if (magfr > frcrit) {
      if (dot3(xr, xr) != 0.0) {
        for (int q = 0; q < 3; q++) xr[q] = -frcrit / (k * magfr) * fr[q] - gamma / k * vrl[q];
        const double f = frcrit / magfr;
        for (int q = 0; q < 3; q++) fr[q] *= f;
      } else {
        fr[0] = fr[1] = fr[2] = 0.0;
      }
    }
    if (s.energy) s.el_r = 0.5 * k * dot3(xr, xr);
    if (s.advance) for (int q = 0; q < 3; q++) h[q] = xr[q];
    double tr[3];
    detail::cross3(s.n, fr, tr);
    for (int q = 0; q < 3; q++) {
      res.torque_i[q] += s.reff * tr[q];
      if (!s.wall) res.torque_j[q] -= s.reff * tr[q];
    }
  }
};

/// The rolling models (the registration: one line per model).
using RollingModel = std::variant<RollingNone, RollingSDS>;

}    // namespace viscontact

#endif
