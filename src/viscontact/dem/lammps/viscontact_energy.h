/* viscontact_energy.h -- the energy count of one contact (on with track_energy): each
   sub-model gives its force (in ContactState) and its elastic energy; this ledger turns them
   into the energy each mechanism dissipated over the step.

   A force's work over a step is what velocity Verlet does: the trapezoid (W_last + W_now)/2,
   each half the force (and its torques) of one evaluation, in that evaluation's geometry
   (normal, lever arms), on this step's displacements v dt and w dt (the velocities an
   evaluation sees are the half-step ones, so v dt is exactly the step's displacement).  So that
   kinetic + rotational + elastic + dissipated is conserved to O(dt^2) (the normal spring's
   exact U against the trapezoid):
     normal damping  -W of F_d n = (F_n - F_ne) n      (the clamp included)
     tangential damping  -W of the tangential dashpot, -eta_t v_tr, with its torques
     sliding  -W of the tangential force minus the change of the spring energy, minus the
       tangential damping: the Coulomb slip, the energy the mindlin stiffness change and the
       rescale take from the spring, and the turning of the spring with the contact plane
       (native's rotate-and-rescale of the history, O(dt) over a run, which the spring energy
       alone does not see)
     rolling, twisting  -W of the rolling / twisting torque minus the change of its spring
       energy (dashpot, slip, and the spring's turning with the plane)
     adhesion hysteresis (jkr, dmt): when a contact forms, the energy its elastic force's jump
       takes, -U(delta) - W_now of F_ne over the step before (no force at its start); when it
       ends (pull-off), the energy it still holds (release()).
   Elastic: normal U(delta) (viscontact_normal.h), tangential (1/2) k_t |xi|^2 (|h|^2/(2 k_t)
   for the force forms), rolling (1/2) KR |xi_R|^2, twisting (1/2) k_tw xi_tw^2.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_ENERGY_H
#define VISCONTACT_ENERGY_H

#include "viscontact_submodel.h"

namespace viscontact {

/// The last forces and pending half-step works kept per contact for the energy count
/// (HistorySlots::damp, track_energy only).
constexpr int NDAMP = 23;
/// The works of the last evaluation's forces over this step, the first half of the trapezoid:
/// normal damping, tangential damping, rolling, twisting, elastic normal, tangential spring.
constexpr int NLAST = 6;

/// History slot offsets of a model (-1: absent).  The total is size.
struct HistorySlots {
  int touch = 0;         ///< 1 while the contact exists (jkr: until pull-off)
  int damping = -1;      ///< the damping law's (Jian's contact start time)
  int energy = -1;       ///< the contact's accumulated dissipated energy (track_energy)
  int elastic = -1;      ///< its elastic energy parts at the last step (NELASTIC, track_energy)
  /// the last evaluation's forces in its geometry, for the first half of each force's work
  /// over this step (the trapezoid of velocity Verlet): 0 normal F_d, 1-3 tangential dashpot
  /// force, 4-6 rolling pseudo-force F_r, 7 twisting torque, 14-16 the normal n, 17-19 the
  /// tangential force F_t, 20-21 the lever arms d_i + d_j and d_i - d_j (so that an i <-> j
  /// flip negates a slot rather than swapping two), 22 the elastic normal force F_ne; 8-13 the
  /// second half of the last forces' work, -(W_last/2) with the last step's velocities (normal
  /// damping, tangential damping, rolling, twisting, the elastic normal force, the tangential
  /// spring), counted by release() when the contact ends and the caller has no velocities for
  /// this step (O(dt^2) per contact).  NDAMP values, track_energy only.
  int damp = -1;
  int tangential = -1;   ///< the tangential model's (xi, a_last)
  int rolling = -1;      ///< the rolling model's (xi_R)
  int twisting = -1;     ///< the twisting model's (xi_tw)
  int size = 1;
};

namespace energy {

/// Signs of the energy slots when i and j swap: the tangential dashpot force, the last n, F_t
/// and d_i - d_j flip; F_d along n and the works do not.
inline void flip(const HistorySlots &slots, double *sign)
{
  if (slots.damp < 0) return;
  for (int k = 1; k < 4; k++) sign[slots.damp + k] = -1.0;
  for (int k = 14; k < 20; k++) sign[slots.damp + k] = -1.0;
  sign[slots.damp + 21] = -1.0;
}

/// The works of the last evaluation's forces (stored in the damp slots) over this step, the
/// first half of the trapezoid, on the bodies [energy] (NLAST values; all 0 for a new contact).
VISCONTACT_ALWAYS_INLINE void last_half_works(const HistorySlots &slots, const double *h,
                                              const ContactGeometry &g, double *w)
{
  using detail::dot3;
  const double *dp = &h[slots.damp];
  const double n_last[3] = {dp[14], dp[15], dp[16]};    // 0 for a new contact: no force then
  const double arms_last[2] = {0.5 * (dp[20] + dp[21]), 0.5 * (dp[20] - dp[21])};
  const double half = 0.5 * g.dt;
  const double vn_last = dot3(n_last, g.vr);
  double rel[3], tr[3];
  detail::relative_rotation(g, rel);
  detail::cross3(n_last, &dp[4], tr);
  const double p_damp = detail::tangential_power(&dp[1], n_last, arms_last, g);
  w[0] = half * dp[0] * vn_last;
  w[1] = half * p_damp;
  w[2] = half * g.reff * dot3(tr, rel);
  w[3] = half * dp[7] * dot3(n_last, rel);
  w[4] = half * dp[22] * vn_last;
  w[5] = half * (detail::tangential_power(&dp[17], n_last, arms_last, g) - p_damp);
}

/// A contact ends: its elastic energy and the second half of its last forces' work into diss
/// (see ContactModel::release); returns the total.
inline double release(const HistorySlots &slots, const double *h, double *diss,
                      const ContactGeometry *now)
{
  if (slots.elastic < 0) return 0.0;
  const double *e = &h[slots.elastic];
  diss[DISS_ADHESION] += e[ELASTIC_NORMAL];
  diss[DISS_SLIDING] += e[ELASTIC_TANGENTIAL];
  diss[DISS_ROLLING] += e[ELASTIC_ROLLING];
  diss[DISS_TWISTING] += e[ELASTIC_TWISTING];
  double p[NLAST];
  if (now) {
    last_half_works(slots, h, *now, p);
    for (double &x : p) x = -x;
  } else {
    for (int k = 0; k < NLAST; k++) p[k] = h[slots.damp + 8 + k];
  }
  diss[DISS_NORMAL_DAMPING] += p[0];
  diss[DISS_TANGENTIAL_DAMPING] += p[1];
  diss[DISS_ROLLING] += p[2];
  diss[DISS_TWISTING] += p[3];
  diss[DISS_ADHESION] += p[4];
  diss[DISS_SLIDING] += p[5];
  return e[0] + e[1] + e[2] + e[3] + p[0] + p[1] + p[2] + p[3] + p[4] + p[5];
}

/// This step's dissipated energy by mechanism and the elastic energies into res; this
/// evaluation's forces, half-works and elastic energies into the damp and elastic slots; with
/// advance, the step's dissipated total into the history.  A run's setup (advance false) writes
/// the slots too: the integrator's first step starts from the setup's forces, so they are the
/// first half of that step's trapezoid (stale slots left an O(dt) gap there for a contact begun
/// at setup, O(dt^2) for one going on).  arms: the lever arms d_i, d_j of the tangential force.
VISCONTACT_ALWAYS_INLINE void count(const HistorySlots &slots, const ContactState &s,
                                    const ContactGeometry &g, const double arms[2],
                                    double *__restrict h, ContactResult &__restrict res)
{
  using detail::dot3;
  const double *n = s.n, vn = s.vn, fn = s.fn, fne = s.fne;
  res.elastic[ELASTIC_NORMAL] = s.U;
  res.elastic[ELASTIC_TANGENTIAL] = s.el_t;
  res.elastic[ELASTIC_ROLLING] = s.el_r;
  res.elastic[ELASTIC_TWISTING] = s.el_w;
  double *dp = &h[slots.damp];
  double wl[NLAST];
  last_half_works(slots, h, g, wl);
  const double half = 0.5 * s.dt;
  const double p_damp = detail::tangential_power(s.fdamp_t, n, arms, g);
  const double p_t = detail::tangential_power(s.ft, n, arms, g);
  // rolling: the torque R* n x F_r on i (minus on j) on w_i - w_j; twisting: tau n likewise
  double tr_now[3];
  detail::cross3(n, s.fr, tr_now);
  const double p_r = s.reff * dot3(tr_now, s.relrot), p_w = s.tau_twist * dot3(n, s.relrot);
  const double dtd = -(wl[1] + half * p_damp);
  const double *el_last = &h[slots.elastic];
  res.dissipated[DISS_NORMAL_DAMPING] = -(wl[0] + half * (fn - fne) * vn);
  res.dissipated[DISS_TANGENTIAL_DAMPING] = dtd;
  res.dissipated[DISS_SLIDING] =
      -(wl[1] + wl[5] + half * p_t) - (s.el_t - el_last[ELASTIC_TANGENTIAL]) - dtd;
  res.dissipated[DISS_ROLLING] = -(wl[2] + half * p_r) - (s.el_r - el_last[ELASTIC_ROLLING]);
  res.dissipated[DISS_TWISTING] = -(wl[3] + half * p_w) - (s.el_w - el_last[ELASTIC_TWISTING]);
  // snap-in (jkr, dmt): the elastic energy jumps from 0 (apart) to U, and the attraction did
  // (F_ne/2) v_n dt over the step before (the trapezoid with no force at its start)
  res.dissipated[DISS_ADHESION] = (s.fresh && s.cohesive) ? -s.U - 0.5 * fne * vn * s.dt : 0.0;
  dp[0] = fn - fne;
  for (int k = 0; k < 3; k++) {
    dp[1 + k] = s.fdamp_t[k];
    dp[4 + k] = s.fr[k];
    dp[14 + k] = n[k];
    dp[17 + k] = s.ft[k];
  }
  dp[7] = s.tau_twist;
  dp[20] = arms[0] + arms[1];
  dp[21] = arms[0] - arms[1];
  dp[22] = fne;
  dp[8] = -half * (fn - fne) * vn;
  dp[9] = -half * p_damp;
  dp[10] = -half * p_r;
  dp[11] = -half * p_w;
  dp[12] = -half * fne * vn;
  dp[13] = -half * (p_t - p_damp);
  double sum = 0.0;
  for (int k = 0; k < NDISS; k++) sum += res.dissipated[k];
  res.power = s.dt > 0.0 ? sum / s.dt : 0.0;
  if (s.advance) h[slots.energy] += sum;
  for (int k = 0; k < NELASTIC; k++) h[slots.elastic + k] = res.elastic[k];
}

}    // namespace energy
}    // namespace viscontact

#endif
