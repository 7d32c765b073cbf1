/* viscontact_contact.h -- the one C++ expression of the viscontact contact model.

   Header-only, no LAMMPS includes: shared by `pair viscontact`, `fix viscontact/wall` and the
   tiny ctypes kernel library that tests it against `viscontact.kernels`.  Units are written
   as SI (kg, m, s, N, Pa); every expression holds in any consistent unit system (LAMMPS `units
   si`, `cgs`, `micro`, ...), with c0 in force time / length^(1+p) of that system.

   Normal law (Hertz spring with the damping terms compared by Jian et al., Powder Technol.
   356 (2019) 735), one contact with overlap delta > 0:

       F_n = k delta^(3/2) + c0 g(t_c) delta^p ddelta,     k = (4/3) E* sqrt(R*)
       g(t) = 1 - exp(-t / tau)   (Jian, tau > 0);   g = 1   (every other law, tau = 0)

   ddelta = d(delta)/dt, positive while the spheres approach; t_c = time since the contact began.
   FORM alpha gives c0 and tau per contact from that contact's m*, R* (Jian et al. 2019's
   non-dimensional damping constant alpha at the reference speed vref):

       c0  = alpha m*^((3-2p)/5) vref^((1-4p)/5) k^((2+2p)/5)
       tau = beta T_ref,   T_ref = (m*^2 / (k^2 vref))^(1/5)

   The sub-models that use this law are composed in viscontact_model.h.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS.
*/
#ifndef VISCONTACT_CONTACT_H
#define VISCONTACT_CONTACT_H

#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

namespace viscontact {

/// The damping laws (in the order of LAW_TABLE); p is the overlap exponent of the damping term.
enum class Law { LH, Ts, KK, Li, Hunt, Jian, Power };

/// One row of the law table: what viscontact.laws says of each law (name as users write it,
/// damping exponent p (-1: the user gives p), whether it takes a relaxation time beta/tau, and
/// the per-contact memory a DEM engine must keep).  The ONLY place a law is named in C++;
/// tests/dem/pair/test_law_table.py checks it against the Python registry.
struct LawInfo {
  Law law;
  const char *name;
  double p;
  bool needs_beta;
  const char *history;    ///< comma-separated names, "" for none
};

constexpr LawInfo LAW_TABLE[] = {
    {Law::LH, "LH", 0.0, false, ""},        // Lee & Herrmann, J. Phys. A 26 (1993) 373
    {Law::Ts, "Ts", 0.25, false, ""},       // Tsuji et al., Powder Technol. 71 (1992) 239
    {Law::KK, "KK", 0.5, false, ""},        // Kuwabara & Kono, Jpn. J. Appl. Phys. 26 (1987) 1230
    {Law::Li, "Li", 1.0, false, ""},        // Lichtensteiger
    {Law::Hunt, "Hunt", 1.5, false, ""},    // Hunt & Crossley, J. Appl. Mech. 42 (1975) 440
    {Law::Jian, "Jian", 0.5, true, "contact_start_time"},    // Jian et al., Powder Technol. 356 (2019) 735
    {Law::Power, "power", -1.0, false, ""},
};
constexpr int NLAWS = sizeof(LAW_TABLE) / sizeof(LAW_TABLE[0]);

/// Law name as users write it (case-insensitive on input).
inline const char *law_name(Law law)
{
  for (const LawInfo &r : LAW_TABLE)
    if (r.law == law) return r.name;
  return "?";
}

/// "LH Ts KK Li Hunt Jian power": the names for error messages.
inline std::string law_names()
{
  std::string out;
  for (const LawInfo &r : LAW_TABLE) out += (out.empty() ? "" : " ") + std::string(r.name);
  return out;
}

/// The laws with a relaxation time (beta / tau), for error messages.
inline std::string beta_law_names()
{
  std::string out;
  for (const LawInfo &r : LAW_TABLE)
    if (r.needs_beta) out += (out.empty() ? "" : " ") + std::string(r.name);
  return out;
}

/// Parse a law name (case-insensitive).  Returns false for an unknown name.
inline bool parse_law(const std::string &name, Law &law)
{
  auto lower = [](std::string x) {
    for (char &c : x) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return x;
  };
  const std::string s = lower(name);
  for (const LawInfo &r : LAW_TABLE) {
    if (lower(r.name) == s) {
      law = r.law;
      return true;
    }
  }
  return false;
}

/// Damping exponent p of a fixed law (LH 0, Ts 1/4, KK 1/2, Li 1, Hunt 3/2, Jian 1/2);
/// -1 for `power`, whose p the user gives.
constexpr double law_exponent(Law law)
{
  for (const LawInfo &r : LAW_TABLE)
    if (r.law == law) return r.p;
  return -1.0;
}

/// One type pair (or one wall) as parsed from the input.
struct LawParams {
  Law law = Law::KK;
  double p = 0.5;           ///< damping exponent (set from the law; `power`: given)
  bool by_alpha = true;     ///< FORM `alpha A vref V [beta B]` (true) or `c0 C [tau S]` (false)
  double alpha = 0.0;       ///< non-dimensional damping constant at vref [-]
  double vref = 0.0;        ///< relative normal impact speed at which alpha applies [m/s]
  double beta = 0.0;        ///< Jian: tau / T_ref [-]
  double c0 = 0.0;          ///< physical damping prefactor [N s / m^(1+p)] (LH: kg/s)
  double tau = 0.0;         ///< Jian: relaxation time [s]
  bool clamp = true;        ///< `end force`: F_n >= 0 (no attraction); `end overlap`: no clamp
};

/// Per-contact coefficients: Hertz stiffness k [N/m^1.5], damping prefactor c0 [N s/m^(1+p)],
/// relaxation time tau [s] (0: no relaxation, g = 1); with tau > 0, the step factors of the
/// relaxation g(t) = 1 - exp(-t/tau) for the time step `step` [s] (relaxation_step): one step
/// advances g to g decay + rise, decay = exp(-dt/tau), rise = 1 - decay.
struct ContactCoeffs {
  double k, c0, tau;
  double decay = 0.0, rise = 1.0, step = -1.0;
};

/// Set cc's step factors of the relaxation for the time step dt [s] (nothing to do when they
/// are for dt already, or when cc has no relaxation time).  Computed once per cached
/// coefficient set and time step, not per contact and step: Jian's g then costs a multiply-add
/// per contact and step instead of an exp.
inline void relaxation_step(ContactCoeffs &cc, double dt)
{
  if (cc.step == dt) return;
  if (cc.tau > 0.0) {
    cc.decay = std::exp(-dt / cc.tau);
    cc.rise = -std::expm1(-dt / cc.tau);
  }
  cc.step = dt;
}

/// 1/E* contribution of one body: (1 - nu^2) / E [1/Pa]; 0 for a rigid body (E = inf).
inline double inverse_Estar_term(double E, double nu) { return (1.0 - nu * nu) / E; }

/// 1/G* contribution of one body: (2 - nu) / G = 2 (2 - nu)(1 + nu) / E [1/Pa] (as LAMMPS's
/// `mix_stiffnessG`).
inline double inverse_Gstar_term(double E, double nu) { return 2.0 * (2.0 - nu) * (1.0 + nu) / E; }

/// E* of two bodies: 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 [Pa] (hertz/material mixing).
inline double mix_Estar(double E1, double nu1, double E2, double nu2)
{
  return 1.0 / (inverse_Estar_term(E1, nu1) + inverse_Estar_term(E2, nu2));
}

/// G* of two bodies: 1/G* = (2-nu1)/G1 + (2-nu2)/G2, G = E / (2 (1 + nu)) [Pa].
inline double mix_Gstar(double E1, double nu1, double E2, double nu2)
{
  return 1.0 / (inverse_Gstar_term(E1, nu1) + inverse_Gstar_term(E2, nu2));
}

/// Hertz stiffness k = (4/3) E* sqrt(R*) [N/m^1.5].
inline double hertz_stiffness(double Estar, double reff) { return 4.0 / 3.0 * Estar * std::sqrt(reff); }

/// Relaxation factor g(t) = 1 - exp(-t/tau) of Jian's law (Jian et al. 2019); 1 when tau <= 0
/// (every other law).  t [s] since the contact began, tau [s].
inline double relaxation(double t, double tau)
{
  if (tau > 0.0) return -std::expm1(-t / tau);
  return 1.0;
}

/// delta^p for delta >= 0 with fast paths for the laws' exponents and the power law's usual
/// 3/4 (p = 0, 1/4, 1/2, 3/4, 1, 3/2: sqrt-based, within an ulp or two of std::pow, at a
/// fraction of its cost), std::pow otherwise.  (3/4 is tested first: law_overlap_power calls
/// this with a run-time p for the power law only.)
inline double overlap_power(double delta, double p)
{
  if (p == 0.75) {
    const double s = std::sqrt(delta);
    return s * std::sqrt(s);
  }
  if (p == 0.0) return 1.0;
  if (p == 0.5) return std::sqrt(delta);
  if (p == 1.0) return delta;
  if (p == 1.5) return delta * std::sqrt(delta);
  if (p == 0.25) return std::sqrt(std::sqrt(delta));
  return std::pow(delta, p);
}

/// delta^p of law L's damping term with its exponent from LAW_TABLE, a constant here: the
/// fast path is chosen at compile time.
template <Law L> inline double fixed_law_power(double delta)
{
  constexpr double p = law_exponent(L);
  static_assert(p >= 0.0, "a law with a fixed exponent");
  return overlap_power(delta, p);
}

/// delta^p of the damping term of `law` (p: its exponent, law_exponent(law) for every law but
/// power): one switch on the law instead of a chain of exponent tests per contact and step.
inline double law_overlap_power(Law law, double delta, double p)
{
  switch (law) {
    case Law::LH: return fixed_law_power<Law::LH>(delta);
    case Law::Ts: return fixed_law_power<Law::Ts>(delta);
    case Law::KK: return fixed_law_power<Law::KK>(delta);
    case Law::Li: return fixed_law_power<Law::Li>(delta);
    case Law::Hunt: return fixed_law_power<Law::Hunt>(delta);
    case Law::Jian: return fixed_law_power<Law::Jian>(delta);
    default: return overlap_power(delta, p);
  }
}

/// Per-contact k, c0, tau from the parsed LawParams, the contact's E* [Pa], m* [kg] and R* [m]
/// (pair: m* = m_i m_j/(m_i+m_j), R* = r_i r_j/(r_i+r_j); wall: m* = m, R* = r).
inline ContactCoeffs contact_coeffs(const LawParams &lp, double Estar, double meff, double reff)
{
  ContactCoeffs cc;
  cc.k = hertz_stiffness(Estar, reff);
  if (lp.by_alpha) {
    const double p = lp.p;
    cc.c0 = lp.alpha * std::pow(meff, (3.0 - 2.0 * p) / 5.0) *
        std::pow(lp.vref, (1.0 - 4.0 * p) / 5.0) * std::pow(cc.k, (2.0 + 2.0 * p) / 5.0);
    cc.tau = (lp.law == Law::Jian) ? lp.beta * std::pow(meff * meff / (cc.k * cc.k * lp.vref), 0.2)
                                   : 0.0;
  } else {
    cc.c0 = lp.c0;
    cc.tau = (lp.law == Law::Jian) ? lp.tau : 0.0;
  }
  return cc;
}

/// x as printf's %g writes it (short, for error messages).
inline std::string format_number(double x)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

/// True when k, c0 and tau are finite numbers (extreme inputs can overflow the alpha form's
/// powers, e.g. vref^((1-4p)/5) for a large p).
inline bool coeffs_finite(const ContactCoeffs &cc)
{
  return std::isfinite(cc.k) && std::isfinite(cc.c0) && std::isfinite(cc.tau);
}

/// "k = ..., c0 = ..., tau = ..." for error messages.
inline std::string describe_coeffs(const ContactCoeffs &cc)
{
  return "k = " + format_number(cc.k) + ", c0 = " + format_number(cc.c0) +
      ", tau = " + format_number(cc.tau);
}

/// The time of the current step [s] as LAMMPS counts it (atime at step atimestep, then dt a
/// step); U is LAMMPS's Update (a template, so that this header needs no LAMMPS include).
template <class U> inline double time_now(const U *update)
{
  return update->atime + (double) (update->ntimestep - update->atimestep) * update->dt;
}

/// Start time [s] of a contact first seen at time t_now with overlap delta and rate ddelta:
/// the overlap is taken back linearly to 0, t0 = t_now - delta/ddelta, but at most one step dt
/// back (t0 in [t_now - dt, t_now]; ddelta <= 0: t0 = t_now).  Jian's clock is t_c = t - t0.
/// Used by pair and wall alike, so that a new contact's clock is second-order in dt.
inline double contact_start_time(double t_now, double dt, double delta, double ddelta)
{
  if (ddelta > 0.0 && delta > 0.0) {
    const double back = delta / ddelta;
    return t_now - (back < dt ? back : dt);
  }
  return t_now;
}

/// vtr = (v_r - (v_r . n) n) - (wr x n) [m/s]: v_r = v_i - v_j, wr = r_i w_i + r_j w_j
/// (wall: wr = r_i w_i, v_j the wall's velocity).  Also returns v_r . n (< 0 approaching).
inline double relative_tangential_velocity(const double vr[3], const double wr[3],
                                           const double n[3], double vtr[3])
{
  const double vnnr = vr[0] * n[0] + vr[1] * n[1] + vr[2] * n[2];
  const double vt0 = vr[0] - vnnr * n[0];
  const double vt1 = vr[1] - vnnr * n[1];
  const double vt2 = vr[2] - vnnr * n[2];
  vtr[0] = vt0 - (wr[1] * n[2] - wr[2] * n[1]);
  vtr[1] = vt1 - (wr[2] * n[0] - wr[0] * n[2]);
  vtr[2] = vt2 - (wr[0] * n[1] - wr[1] * n[0]);
  return vnnr;
}

}    // namespace viscontact

#endif
