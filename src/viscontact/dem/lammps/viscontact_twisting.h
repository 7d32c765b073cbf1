/* viscontact_twisting.h -- the twisting sub-models (LAMMPS pair granular's): none,
   `twisting marshall` (Marshall, J. Comput. Phys. 228 (2009) 1541: k = k_t a^2/2, damping
   eta_t a^2/2, limit (2/3) mu a F0 from the tangential spring) or `twisting sds KT GAMMAT MUT`
   (limit MUT F0, MUT a length as native's code).  The twisting angle xi_tw (1 value per
   contact, keeps its sign when i and j swap) grows by w_tw dt, w_tw = (w_i - w_j) . n; torque
   tau = -k xi_tw - eta w_tw capped at the limit (xi_tw rewritten to match), tau n on i, minus
   on j.  Mixing: geometric means.  Spring energy (1/2) k xi_tw^2.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_TWISTING_H
#define VISCONTACT_TWISTING_H

#include "viscontact_rolling.h"

namespace viscontact {

/// The twisting spring step of both models: stiffness ktw, damping etw, limit tcrit.
VISCONTACT_ALWAYS_INLINE void twisting_step(ContactState &s, double *h, ContactResult &res,
                                            double ktw, double etw, double tcrit)
{
  const double wt = detail::dot3(s.relrot, s.n);
  double &xt = h[0];
  if (s.advance) xt += wt * s.dt;
  double tq = -ktw * xt - etw * wt;
  const double sgn = (wt > 0.0) - (wt < 0.0);
  if (std::fabs(tq) > tcrit) {
    xt = (tcrit * sgn - etw * wt) / ktw;
    tq = -tcrit * sgn;
  }
  if (s.energy) s.el_w = 0.5 * ktw * xt * xt;
  s.tau_twist = tq;
  for (int k = 0; k < 3; k++) {
    res.torque_i[k] += tq * s.n[k];
    if (!s.wall) res.torque_j[k] -= tq * s.n[k];
  }
}

/// No twisting resistance (not a keyword: the default).
struct TwistingNone : NoValues<TwistingNone>, Absent {
  static constexpr const char *NAME = "none";
  int history_size() const { return 0; }
  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &, double *, ContactResult &) const {}
};

/// Marshall's twisting from the tangential spring (needs one: linear_history or mindlin).
struct TwistingMarshall : NoValues<TwistingMarshall> {
  static constexpr const char *NAME = "marshall";
  int history_size() const { return 1; }
  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *h, ContactResult &res) const
  {
    const double a2 = s.a * s.a;
    twisting_step(s, h, res, 0.5 * s.k_t * a2, 0.5 * s.eta_t * a2, 2.0 / 3.0 * s.mu_t * s.a * s.F0);
  }
};

struct TwistingSDS : SDSValues<TwistingSDS> {
  static constexpr const char *NAME = "sds";
  static std::string usage() { return "KT GAMMAT MUT"; }
  std::string parse(const Args &args, size_t &i)
  {
    static const char *const names[3] = {"KT", "GAMMAT", "MUT"};
    return parse_sds(args, i, "twisting", names, PHYSICAL_DOMAIN, k, gamma, mu);
  }
  int history_size() const { return 1; }
  static void flip(double *) {}
  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *h, ContactResult &res) const
  {
    twisting_step(s, h, res, k, gamma, mu * s.F0);
  }
};

/// The twisting models (the registration: one line per model).
using TwistingModel = std::variant<TwistingNone, TwistingMarshall, TwistingSDS>;

}    // namespace viscontact

#endif
