/* viscontact_model.h -- THE contact step of viscontact: one granular contact model per type pair
   (pair viscontact) or per wall type (fix viscontact/wall), composed of sub-models, evaluated by
   one call.  Header-only, no LAMMPS includes (also built into the ctypes test kernel).

   Sub-models (one of each per model):
     normal      hertz/material E NU | dmt E NU W | jkr E NU W
     damping     one of the viscoelastic laws of viscontact_contact.h (LH Ts KK Li Hunt Jian power)
     tangential  none | linear_nohistory XGAMMA MU | linear_history KT XGAMMA MU
                 | mindlin[_rescale][/force] KT|NULL XGAMMA MU   (short form: mindlin MU)
     rolling     none | sds KR GAMMAR MUR
     twisting    none | marshall | sds KT GAMMAT MUT
     heat        none | area K

   Order of one evaluation (as LAMMPS pair granular, stable 22Jul2025): contact radius a, elastic
   normal force F_ne, damping prefactor eta_n and F_d, F_n = F_ne + F_d (clamped at 0 with
   `end force`), critical force F0, tangential force, torques, rolling, twisting, heat.

   Normal models (K. L. Johnson, Contact Mechanics, CUP 1985, ch. 4 and 5; Johnson, Kendall,
   Roberts, Proc. R. Soc. A 324 (1971) 301; Derjaguin, Muller, Toporov, J. Colloid Interface
   Sci. 53 (1975) 314), k = (4/3) E*, k_H = k sqrt(R*):
     hertz  a = sqrt(R* delta), F_ne = k a delta,                       F0 = |F_n|
     dmt    a = sqrt(R* delta), F_ne = k a delta - 4 pi W R*,           F0 = |F_ne + 8 pi W R*|
     jkr    delta = a^2/R* - 2 sqrt(pi W a / E*), F_ne = k a^3/R* - 4 sqrt(pi W E*) a^(3/2),
            F0 = |F_ne + 6 pi W R*|; the contact forms at delta > 0 and lives until
            delta < -delta_c, delta_c = (3 pi^2/16)^(1/3) (R* W^2/E*^2)^(1/3).
   Damping: F_d = c0 g(t_c) delta_a^p ddelta with delta_a = a^2/R* (= delta for hertz, dmt),
   ddelta = -v_n; the tangential damping is XGAMMA times the (unclamped) prefactor.

   Energy (per evaluation that advances the history): dissipated energy by mechanism
   (DISS_* below) and the elastic energy stored now (ELASTIC_*).  A force's work over a step is
   what velocity Verlet does: the trapezoid (W_last + W_now)/2, each half the force (and its
   torques) of one evaluation, in that evaluation's geometry (normal, lever arms), on this
   step's displacements v dt and w dt (the velocities an evaluation sees are the half-step
   ones, so v dt is exactly the step's displacement).  So that kinetic + rotational + elastic +
   dissipated is conserved to O(dt^2) (the normal spring's exact U against the trapezoid):
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
   Elastic: normal U(delta) = int F_ne d(delta) (hertz (2/5) k_H delta^(5/2), dmt minus F_po
   delta, jkr from -delta_c), tangential (1/2) k_t |xi|^2 (|h|^2/(2 k_t) for the force forms),
   rolling (1/2) KR |xi_R|^2, twisting (1/2) k_tw xi_tw^2.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_MODEL_H
#define VISCONTACT_MODEL_H

#include "viscontact_contact.h"

#include <cmath>
#include <string>

/// The contact step is inlined into the callers' loops (pair, wall), so that the geometry and
/// the result live in registers rather than in memory (measured: about 30 % of the pair's time).
#if defined(__GNUC__)
#define VISCONTACT_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define VISCONTACT_ALWAYS_INLINE inline
#endif

namespace viscontact {

/* ---- sub-model kinds and their parameters ---------------------------------------------- */

enum class NormalKind { Hertz, DMT, JKR };
enum class TangentialKind {
  None, LinearNoHistory, LinearHistory, Mindlin, MindlinRescale, MindlinForce, MindlinRescaleForce
};
enum class RollingKind { None, SDS };
enum class TwistingKind { None, Marshall, SDS };
enum class HeatKind { None, Area };

/// Dissipation mechanisms, in the order of every energy column.
enum Dissipation {
  DISS_NORMAL_DAMPING = 0, DISS_TANGENTIAL_DAMPING, DISS_SLIDING, DISS_ROLLING, DISS_TWISTING,
  DISS_ADHESION, NDISS
};
/// Elastic energy parts, in the order of every energy column.
enum Elastic { ELASTIC_NORMAL = 0, ELASTIC_TANGENTIAL, ELASTIC_ROLLING, ELASTIC_TWISTING, NELASTIC };

struct NormalParams {
  NormalKind kind = NormalKind::Hertz;
  double W = 0.0;    ///< surface energy per area (native's cohesion) [energy/length^2]
};
struct TangentialParams {
  TangentialKind kind = TangentialKind::None;
  double kt = 0.0;        ///< KT (linear_history: force/length; mindlin: force/length^2)
  bool kt_null = false;   ///< mindlin family: KT given as NULL (k = 8 G*)
  double xgamma = 0.0;    ///< tangential damping / normal damping prefactor [-]
  double mu = 0.0;        ///< sliding friction coefficient [-]
};
struct RollingParams {
  RollingKind kind = RollingKind::None;
  double k = 0.0, gamma = 0.0, mu = 0.0;    ///< KR [force/length], GAMMAR, MUR
};
struct TwistingParams {
  TwistingKind kind = TwistingKind::None;
  double k = 0.0, gamma = 0.0, mu = 0.0;    ///< sds: KT [torque/rad], GAMMAT, MUT [length]
};
struct HeatParams {
  HeatKind kind = HeatKind::None;
  double k = 0.0;    ///< conductivity K [power/(length^2 temperature)]
};

/* ---- one contact: what goes in, what comes out ------------------------------------------ */

/// Geometry and kinematics of one contact.  Pair: n = (x_i - x_j)/r, r_j > 0.  Wall: n from the
/// wall to the sphere, wall = true (lever arm r_i, no torque on j, omega_j = 0).
struct ContactGeometry {
  double n[3];                  ///< unit normal, from j (or the wall) to i
  double delta;                 ///< overlap r_i + r_j - r (wall: r_i - distance) [length]
  double r_i, r_j;              ///< radii (wall: r_j unused)
  double reff, meff;            ///< R*, m*
  double vr[3];                 ///< v_i - v_j (wall: v_i - v_wall)
  double omega_i[3], omega_j[3];
  double dt, t_now;             ///< time step, time now
  double T_i = 0.0, T_j = 0.0;  ///< temperatures (heat area)
  bool wall = false;
  const ContactCoeffs *coeffs = nullptr;    ///< per-contact k_H, c0, tau if the caller caches them
};

/// Everything one evaluation produces.
struct ContactResult {
  double force[3];       ///< total contact force on i (j gets its negative)
  double torque_i[3], torque_j[3];
  double heat;           ///< heat flow into i (j gets its negative)
  double fn, fne, fdamp; ///< F_n (after the clamp), F_ne (elastic), F_n - F_ne
  double ft[3], fr[3];   ///< tangential force on i, rolling pseudo-force
  double tau_twist;      ///< twisting torque magnitude along n on i
  double a;              ///< contact radius
  double dissipated[NDISS];   ///< energy dissipated over this step (dt), per mechanism; added to
                              ///< the contact's history only when the history advances
  double elastic[NELASTIC];   ///< elastic energy stored now
  double power;               ///< total dissipated power of the step (sum dissipated / dt)

  /// The mechanics times f (a special_bonds factor, 0 < f < 1, as pair granular applies it):
  /// forces, torques and so the work, dissipated and elastic energies.  The heat flow and the
  /// contact radius stay (pair granular conducts heat through a bonded contact unscaled).
  void scale(double f)
  {
    for (int k = 0; k < 3; k++) {
      force[k] *= f;
      torque_i[k] *= f;
      torque_j[k] *= f;
      ft[k] *= f;
      fr[k] *= f;
    }
    fn *= f;
    fne *= f;
    fdamp *= f;
    tau_twist *= f;
    for (double &d : dissipated) d *= f;
    for (double &e : elastic) e *= f;
    power *= f;
  }
};

/// The last forces and pending half-step works kept per contact for the energy count
/// (HistorySlots::damp, track_energy only).
constexpr int NDAMP = 23;

/// History slot offsets of a model (-1: absent).  The total is history_size().
struct HistorySlots {
  int touch = 0;       ///< 1 while the contact exists (jkr: until pull-off)
  int relax = -1;      ///< relaxation g = 1 - exp(-t_c/tau) at the last step (Jian's clock)
  int energy = -1;     ///< the contact's accumulated dissipated energy (track_energy)
  int elastic = -1;    ///< its elastic energy parts at the last step (NELASTIC, track_energy)
  int xi = -1;         ///< tangential displacement xi or elastic force h (3)
  int a_prev = -1;     ///< contact radius of the last step (the rescale models)
  int roll = -1;       ///< rolling displacement (3)
  int twist = -1;      ///< twisting angle (1)
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
  int size = 1;
};

/* ---- normal-model helpers ----------------------------------------------------------------- */

/// JKR contact radius on the stable branch for overlap delta (the closed-form root of
/// delta = a^2/R - 2 sqrt(pi W a/E*), as LAMMPS granular's), dR = delta R*.
inline double jkr_contact_radius(double reff, double delta, double W, double Estar)
{
  const double PI = 3.14159265358979323846;
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
  const double PI = 3.14159265358979323846;
  return 8.0 * Estar / (15.0 * reff * reff) * a * a * a * a * a -
      8.0 / (3.0 * reff) * std::sqrt(PI * W * Estar) * a * a * a * std::sqrt(a) +
      2.0 * PI * W * a * a;
}

/* ---- the model ---------------------------------------------------------------------------- */

class ContactModel {
 public:
  NormalParams normal;
  LawParams law;    ///< damping law, clamp (`end force`), E*, G* (friction/mu: legacy fields)
  TangentialParams tangential;
  RollingParams rolling;
  TwistingParams twisting;
  HeatParams heat;
  /// Count energies (dissipated by mechanism, elastic parts, per-contact history slots).  Off,
  /// the step skips that bookkeeping (the forces are the same) and ContactResult's energy
  /// fields are 0.  Set before setup().
  bool track_energy = true;

  /// Lay out the history slots; call after the parameters are set (and after mixing).  The
  /// force_* flags reserve a slot even if this model does not use it, so that every type pair
  /// of a pair style shares one layout (one history size, one flip rule).
  void setup(bool force_xi = false, bool force_aprev = false, bool force_roll = false,
             bool force_twist = false, bool force_t0 = false)
  {
    int n = 1;
    slots = HistorySlots();
    if (LAW_TABLE[static_cast<int>(law.law)].needs_beta || force_t0) slots.relax = n++;
    if (track_energy) {
      slots.energy = n++;
      slots.elastic = n;
      n += NELASTIC;
      slots.damp = n;
      n += NDAMP;
    }
    if (has_tangential_history() || force_xi) { slots.xi = n; n += 3; }
    if (needs_aprev() || force_aprev) slots.a_prev = n++;
    if (rolling.kind == RollingKind::SDS || force_roll) { slots.roll = n; n += 3; }
    if (twisting.kind != TwistingKind::None || force_twist) slots.twist = n++;
    slots.size = n;
  }
  int history_size() const { return slots.size; }
  const HistorySlots &history_slots() const { return slots; }

  /// Sign of each history slot when a pair's stored orientation flips (i <-> j): -1 for the
  /// tangential, rolling and twisting displacements, +1 for everything else.  sign[size].
  void history_signs(double *sign) const
  {
    for (int k = 0; k < slots.size; k++) sign[k] = 1.0;
    // seen from j, n and v_t flip, so xi and the tangential dashpot force do; the rolling
    // velocity R* (w_i - w_j) x n and the twisting rate (w_i - w_j) . n do not (both factors
    // flip), so the rolling and twisting displacements and dashpots keep their sign (native
    // pair granular negates them too, which corrupts a contact whose pair order changes at a
    // rebuild, migration or restart); F_d along n and the works do not flip; the last n, F_t
    // and d_i - d_j do
    if (slots.xi >= 0) for (int k = 0; k < 3; k++) sign[slots.xi + k] = -1.0;
    if (slots.damp >= 0) {
      for (int k = 1; k < 4; k++) sign[slots.damp + k] = -1.0;
      for (int k = 14; k < 20; k++) sign[slots.damp + k] = -1.0;
      sign[slots.damp + 21] = -1.0;
    }
  }

  /// The last step's contact radius is kept by the rescale models (native).
  bool needs_aprev() const { return rescale(); }
  bool cohesive() const { return normal.kind != NormalKind::Hertz; }
  bool beyond_contact() const { return normal.kind == NormalKind::JKR; }
  bool has_tangential_history() const
  {
    return tangential.kind != TangentialKind::None &&
        tangential.kind != TangentialKind::LinearNoHistory;
  }
  bool rescale() const
  {
    return tangential.kind == TangentialKind::MindlinRescale ||
        tangential.kind == TangentialKind::MindlinRescaleForce;
  }
  bool force_history() const
  {
    return tangential.kind == TangentialKind::MindlinForce ||
        tangential.kind == TangentialKind::MindlinRescaleForce;
  }
  bool mindlin() const
  {
    return tangential.kind == TangentialKind::Mindlin || rescale() || force_history();
  }
  /// Tangential stiffness coefficient: KT, or 8 G* for mindlin with NULL.
  double tangential_k() const { return tangential.kt_null ? 8.0 * law.Gstar : tangential.kt; }

  /// Extra reach beyond r_i + r_j of a contact of effective radius reff (jkr: delta_c).
  double pulloff_distance(double reff) const
  {
    return normal.kind == NormalKind::JKR ? jkr_pulloff_distance(reff, normal.W, law.Estar) : 0.0;
  }

  /// Does the contact exist?  rsq: squared distance, radsum: r_i + r_j (wall: r_i and rsq the
  /// squared distance to the wall), touched: it existed at the last step.
  bool touching(double rsq, double radsum, double reff, bool touched) const
  {
    if (touched && normal.kind == NormalKind::JKR) {
      const double d = radsum + pulloff_distance(reff);
      return rsq < d * d;
    }
    return rsq < radsum * radsum;
  }

  /// When a contact ends (apart, or beyond pull-off), the elastic energy it still holds is lost,
  /// and so is the second half of its last forces' work (they acted over the step that parted
  /// it): adds both to diss[NDISS] (normal part: adhesion hysteresis, the pull-off jump;
  /// springs: sliding, rolling, twisting) and returns the total.  now: this step's velocities
  /// and dt (vr, omega_i, omega_j, reff, dt, wall; the rest unused), or nullptr where the caller
  /// has none (the last step's are used then).
  double release(const double *h, double *diss, const ContactGeometry *now = nullptr) const
  {
    if (slots.elastic < 0) return 0.0;
    const double *e = &h[slots.elastic];
    diss[DISS_ADHESION] += e[ELASTIC_NORMAL];
    diss[DISS_SLIDING] += e[ELASTIC_TANGENTIAL];
    diss[DISS_ROLLING] += e[ELASTIC_ROLLING];
    diss[DISS_TWISTING] += e[ELASTIC_TWISTING];
    double p[NLAST];
    if (now) {
      last_half_works(h, *now, p);
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

  /// THE contact step.  history: history_size() values of this contact (touch slot 0: a new
  /// contact, which is initialised here).  advance = false in a run's setup force call and in
  /// single(): displacements are not incremented and no energy is counted (the Coulomb cap and
  /// the rescale still rewrite the tangential history, as native).
  void evaluate(const ContactGeometry &g, double *h, bool advance, ContactResult &res) const;

 private:
  HistorySlots slots;
  /// The works of the last evaluation's forces (in its geometry, stored in the damp slots) over
  /// this step, the first half of the trapezoid, on the bodies [energy]: normal damping,
  /// tangential damping, rolling, twisting, elastic normal, tangential spring (force minus
  /// dashpot).  All 0 for a new contact.
  static constexpr int NLAST = 6;
  void last_half_works(const double *h, const ContactGeometry &g, double *w) const;
};

/* ---- implementation ------------------------------------------------------------------------ */

namespace detail {
inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void cross3(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
/// Power of a tangential force F on i (-F on j) with its torques -d_i (n x F) on i and
/// -d_j (n x F) on j: F . v_r - (n x F) . (d_i w_i + d_j w_j) (a wall: no j).
inline double tangential_power(const double *F, const double *n, const double *d,
                               const ContactGeometry &g)
{
  double nxF[3], w[3];
  cross3(n, F, nxF);
  for (int k = 0; k < 3; k++) w[k] = d[0] * g.omega_i[k] + (g.wall ? 0.0 : d[1] * g.omega_j[k]);
  return dot3(F, g.vr) - dot3(nxF, w);
}

/// w_i - w_j (a wall: w_i).
inline void relative_rotation(const ContactGeometry &g, double *rel)
{
  for (int k = 0; k < 3; k++) rel[k] = g.wall ? g.omega_i[k] : g.omega_i[k] - g.omega_j[k];
}

/// Project v onto the plane normal to n and restore its length.
inline void rotate_rescale(double *v, const double *n)
{
  const double len = std::sqrt(dot3(v, v));
  const double vn = dot3(v, n);
  for (int k = 0; k < 3; k++) v[k] -= vn * n[k];
  const double plen = std::sqrt(dot3(v, v));
  const double s = plen > 0.0 ? len / plen : 0.0;
  for (int k = 0; k < 3; k++) v[k] *= s;
}
}    // namespace detail

inline void ContactModel::last_half_works(const double *h, const ContactGeometry &g, double *w) const
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

VISCONTACT_ALWAYS_INLINE void ContactModel::evaluate(const ContactGeometry &g, double *__restrict h, bool advance,
                                   ContactResult &__restrict res) const
{
  using detail::cross3;
  using detail::dot3;
  const double PI = 3.14159265358979323846;
  // local copies: the compiler need not reload them after each store into h or res
  const double n[3] = {g.n[0], g.n[1], g.n[2]};
  const double delta = g.delta, reff = g.reff, dt = g.dt;

  // kinematics: v_n (< 0 approaching), slip velocity v_tr = v_t - (r_i w_i + r_j w_j) x n
  const double rj = g.wall ? 0.0 : g.r_j;
  double wr[3], vtr[3];
  for (int k = 0; k < 3; k++) wr[k] = g.r_i * g.omega_i[k] + rj * g.omega_j[k];
  const double vn = relative_tangential_velocity(g.vr, wr, n, vtr);
  const double ddelta = -vn;

  // a new contact: fresh history and clock
  const bool fresh = h[slots.touch] == 0.0;
  if (fresh) {
    for (int k = 0; k < slots.size; k++) h[k] = 0.0;
    h[slots.touch] = 1.0;
  }

  // (2) contact radius, (3) elastic normal force and potential
  ContactCoeffs cc = g.coeffs ? *g.coeffs : contact_coeffs(law, g.meff, reff);
  // Jian's relaxation g(t_c) = 1 - exp(-t_c/tau), t_c the time since the contact began: a new
  // contact starts its clock at most one step back (contact_start_time); each regular step
  // then advances the stored g exactly by g <- g exp(-dt/tau) + 1 - exp(-dt/tau), whatever dt
  // is at that step (the factors cached per coefficient set and dt: relaxation_step); a run's
  // setup and single() (advance false) read g as it is
  double grel = 1.0;
  if (slots.relax >= 0 && cc.tau > 0.0) {
    if (fresh) {
      const double t0 = contact_start_time(g.t_now, dt, delta, ddelta);
      h[slots.relax] = relaxation(g.t_now - t0, cc.tau);
    } else if (advance) {
      if (!g.coeffs) relaxation_step(cc, dt);
      h[slots.relax] = h[slots.relax] * cc.decay + cc.rise;
    }
    grel = h[slots.relax];
  }
  const double kmat = 4.0 / 3.0 * law.Estar;
  const bool E_on = track_energy;
  double a, fne, fpo = 0.0, delta_a, U = 0.0;
  if (normal.kind == NormalKind::JKR) {
    const double W = normal.W, E = law.Estar;
    a = jkr_contact_radius(reff, delta, W, E);
    const double a2 = a * a;
    fne = kmat * a * a2 / reff - 2.0 * PI * a2 * std::sqrt(4.0 * W * E / (PI * a));
    fpo = 3.0 * PI * W * reff;
    delta_a = a2 / reff;
    if (E_on) {
      const double ac = std::cbrt(9.0 * PI * W * reff * reff / (4.0 * E));
      U = jkr_energy_primitive(a, reff, W, E) - jkr_energy_primitive(ac, reff, W, E);
    }
  } else {
    const double dpos = delta > 0.0 ? delta : 0.0;
    a = std::sqrt(reff * dpos);
    fne = kmat * a * dpos;
    U = 0.4 * fne * dpos;
    if (normal.kind == NormalKind::DMT) {
      fpo = 4.0 * PI * normal.W * reff;
      fne -= fpo;
      U -= fpo * dpos;
    }
    delta_a = dpos;
  }
  res.a = a;

  // (4) damping prefactor and force, (5) total normal force and clamp
  const double eta_n = cc.c0 * grel * overlap_power(delta_a, law.p);
  const double fd = eta_n * ddelta;
  double fn = fne + fd;
  if (law.clamp && fn < 0.0) fn = 0.0;
  res.fne = fne;
  res.fn = fn;
  res.fdamp = fn - fne;

  // (6) critical force
  const double F0 = cohesive() ? std::fabs(fne + 2.0 * fpo) : std::fabs(fn);

  // (7) tangential force
  double *ft = res.ft;
  ft[0] = ft[1] = ft[2] = 0.0;
  const double eta_t = tangential.xgamma * eta_n;
  const double fscrit = tangential.mu * F0;
  double el_t = 0.0;
  double fdamp_t[3] = {0.0, 0.0, 0.0};    // the tangential dashpot force this step
  if (tangential.kind == TangentialKind::LinearNoHistory) {
    const double vrel = std::sqrt(dot3(vtr, vtr));
    if (vrel != 0.0) {
      const double fmag = eta_t * vrel;
      const double s = (fmag < fscrit ? fmag : fscrit) / vrel;
      for (int k = 0; k < 3; k++) ft[k] = -s * vtr[k];
      for (int k = 0; k < 3; k++) fdamp_t[k] = ft[k];
    }
  } else if (tangential.kind != TangentialKind::None) {
    double *xi = &h[slots.xi];
    const bool force_form = force_history();
    const double kt = mindlin() ? tangential_k() * a : tangential.kt;
    // spring energy: (1/2) k |xi|^2, or |h|^2 / (2 k) for the force forms
    auto energy = [force_form](const double *x, double k) {
      return force_form ? (k > 0.0 ? 0.5 * dot3(x, x) / k : 0.0) : 0.5 * k * dot3(x, x);
    };
    if (rescale() && a < h[slots.a_prev]) {
      const double s = a / h[slots.a_prev];
      for (int k = 0; k < 3; k++) xi[k] *= s;
    }
    if (advance) {
      const double rsht = std::fabs(dot3(xi, n));
      if ((force_form ? rsht : rsht * kt) > 1e-10 * fscrit) detail::rotate_rescale(xi, n);
    }
    if (advance) {
      for (int k = 0; k < 3; k++) xi[k] += force_form ? -kt * dt * vtr[k] : dt * vtr[k];
      if (rescale()) h[slots.a_prev] = a;
    }
    double fdmp[3];
    for (int k = 0; k < 3; k++) {
      fdmp[k] = -eta_t * vtr[k];
      ft[k] = (force_form ? xi[k] : -kt * xi[k]) + fdmp[k];
    }
    for (int k = 0; k < 3; k++) fdamp_t[k] = fdmp[k];
    const double magfs = std::sqrt(dot3(ft, ft));
    if (magfs > fscrit) {
      if (dot3(xi, xi) != 0.0) {
        const double s = fscrit / magfs;
        const double back = force_form ? 1.0 : -1.0 / kt;
        for (int k = 0; k < 3; k++) {
          ft[k] *= s;
          xi[k] = (ft[k] - fdmp[k]) * back;
        }
        // the capped force is the rescaled spring plus the whole dashpot (native's rewrite of
        // xi), so the whole dashpot still works: sliding is the rest of the force's work
      } else {
        ft[0] = ft[1] = ft[2] = 0.0;
        fdamp_t[0] = fdamp_t[1] = fdamp_t[2] = 0.0;
      }
    }
    if (E_on) el_t = energy(xi, kt);
  }

  // (8) torques of the tangential force
  double nxf[3];
  cross3(n, ft, nxf);
  const double di = g.wall ? g.r_i : g.r_i - 0.5 * delta;
  const double dj = g.r_j - 0.5 * delta;
  for (int k = 0; k < 3; k++) {
    res.torque_i[k] = -di * nxf[k];
    res.torque_j[k] = g.wall ? 0.0 : -dj * nxf[k];
  }

  // (9) rolling
  double *fr = res.fr;
  fr[0] = fr[1] = fr[2] = 0.0;
  double relrot[3];
  detail::relative_rotation(g, relrot);
  double el_r = 0.0;
  if (rolling.kind == RollingKind::SDS) {
    double vrl[3];
    cross3(relrot, n, vrl);
    for (int k = 0; k < 3; k++) vrl[k] *= reff;
    double xr[3] = {h[slots.roll], h[slots.roll + 1], h[slots.roll + 2]};
    const double kr = rolling.k, frcrit = rolling.mu * F0;
    if (advance && std::fabs(dot3(xr, n)) * kr > 1e-10 * frcrit) detail::rotate_rescale(xr, n);
    if (advance) for (int k = 0; k < 3; k++) xr[k] += dt * vrl[k];
    for (int k = 0; k < 3; k++) fr[k] = -kr * xr[k] - rolling.gamma * vrl[k];
    const double magfr = std::sqrt(dot3(fr, fr));
    if (magfr > frcrit) {
      if (dot3(xr, xr) != 0.0) {
        for (int k = 0; k < 3; k++) xr[k] = -frcrit / (kr * magfr) * fr[k] - rolling.gamma / kr * vrl[k];
        const double s = frcrit / magfr;
        for (int k = 0; k < 3; k++) fr[k] *= s;
      } else {
        fr[0] = fr[1] = fr[2] = 0.0;
      }
    }
    el_r = 0.5 * kr * dot3(xr, xr);
    if (advance) for (int k = 0; k < 3; k++) h[slots.roll + k] = xr[k];
    double tr[3];
    cross3(n, fr, tr);
    for (int k = 0; k < 3; k++) {
      res.torque_i[k] += reff * tr[k];
      if (!g.wall) res.torque_j[k] -= reff * tr[k];
    }
  }

  // (10) twisting
  res.tau_twist = 0.0;
  double el_w = 0.0;
  if (twisting.kind != TwistingKind::None) {
    double ktw, etw, tcrit;
    if (twisting.kind == TwistingKind::Marshall) {
      ktw = 0.5 * tangential_k() * a * a;
      etw = 0.5 * eta_t * a * a;
      tcrit = 2.0 / 3.0 * tangential.mu * a * F0;
    } else {
      ktw = twisting.k;
      etw = twisting.gamma;
      tcrit = twisting.mu * F0;
    }
    const double wt = dot3(relrot, n);
    double &xt = h[slots.twist];
    if (advance) xt += wt * dt;
    double tq = -ktw * xt - etw * wt;
    const double sgn = (wt > 0.0) - (wt < 0.0);
    if (std::fabs(tq) > tcrit) {
      xt = (tcrit * sgn - etw * wt) / ktw;
      tq = -tcrit * sgn;
    }
    el_w = 0.5 * ktw * xt * xt;
    res.tau_twist = tq;
    for (int k = 0; k < 3; k++) {
      res.torque_i[k] += tq * n[k];
      if (!g.wall) res.torque_j[k] -= tq * n[k];
    }
  }


  // (11) heat
  res.heat = heat.kind == HeatKind::Area ? heat.k * PI * a * a * (g.T_j - g.T_i) : 0.0;

  for (int k = 0; k < 3; k++) res.force[k] = fn * n[k] + ft[k];

  if (!E_on) {
    for (int k = 0; k < NDISS; k++) res.dissipated[k] = 0.0;
    for (int k = 0; k < NELASTIC; k++) res.elastic[k] = 0.0;
    res.power = 0.0;
    return;
  }
  res.elastic[ELASTIC_NORMAL] = U;
  res.elastic[ELASTIC_TANGENTIAL] = el_t;
  res.elastic[ELASTIC_ROLLING] = el_r;
  res.elastic[ELASTIC_TWISTING] = el_w;
  // each force's work over this step: the trapezoid of the last evaluation's force in its
  // geometry and this one's, both on this step's displacements (see the head of this file)
  double *dp = &h[slots.damp];
  double wl[NLAST];
  last_half_works(h, g, wl);
  const double arms[2] = {di, g.wall ? 0.0 : dj};
  const double half = 0.5 * dt;
  const double p_damp = detail::tangential_power(fdamp_t, n, arms, g);
  const double p_t = detail::tangential_power(ft, n, arms, g);
  // rolling: the torque R* n x F_r on i (minus on j) on w_i - w_j; twisting: tau n likewise
  double tr_now[3];
  cross3(n, fr, tr_now);
  const double p_r = reff * dot3(tr_now, relrot), p_w = res.tau_twist * dot3(n, relrot);
  const double dtd = -(wl[1] + half * p_damp);
  const double *el_last = &h[slots.elastic];
  res.dissipated[DISS_NORMAL_DAMPING] = -(wl[0] + half * (fn - fne) * vn);
  res.dissipated[DISS_TANGENTIAL_DAMPING] = dtd;
  res.dissipated[DISS_SLIDING] =
      -(wl[1] + wl[5] + half * p_t) - (el_t - el_last[ELASTIC_TANGENTIAL]) - dtd;
  res.dissipated[DISS_ROLLING] = -(wl[2] + half * p_r) - (el_r - el_last[ELASTIC_ROLLING]);
  res.dissipated[DISS_TWISTING] = -(wl[3] + half * p_w) - (el_w - el_last[ELASTIC_TWISTING]);
  // snap-in (jkr, dmt): the elastic energy jumps from 0 (apart) to U, and the attraction did
  // (F_ne/2) v_n dt over the step before (the trapezoid with no force at its start)
  res.dissipated[DISS_ADHESION] = (fresh && cohesive()) ? -U - 0.5 * fne * vn * dt : 0.0;
  if (advance) {
    dp[0] = fn - fne;
    for (int k = 0; k < 3; k++) {
      dp[1 + k] = fdamp_t[k];
      dp[4 + k] = fr[k];
      dp[14 + k] = n[k];
      dp[17 + k] = ft[k];
    }
    dp[7] = res.tau_twist;
    dp[20] = arms[0] + arms[1];
    dp[21] = arms[0] - arms[1];
    dp[22] = fne;
    dp[8] = -half * (fn - fne) * vn;
    dp[9] = -half * p_damp;
    dp[10] = -half * p_r;
    dp[11] = -half * p_w;
    dp[12] = -half * fne * vn;
    dp[13] = -half * (p_t - p_damp);
  }
  double sum = 0.0;
  for (int k = 0; k < NDISS; k++) sum += res.dissipated[k];
  res.power = dt > 0.0 ? sum / dt : 0.0;
  if (advance && E_on) {
    h[slots.energy] += sum;
    for (int k = 0; k < NELASTIC; k++) h[slots.elastic + k] = res.elastic[k];
  }
}

}    // namespace viscontact

#endif
