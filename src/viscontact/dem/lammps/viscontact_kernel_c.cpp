/* extern "C" entry points for the ctypes tests (tests/dem/pair/test_cpp_kernel.py): every one
   runs the shipped contact model (viscontact_model.h: ContactModel::evaluate, as pair and wall call it)
   on one contact, so that the tests check the code the plugin runs against the Python
   formulas.  Built by viscontact.dem.plugin.kernel_library_path() into a tiny library of its
   own: no LAMMPS. */
#include "viscontact_model.h"

namespace {
namespace vc = viscontact;

/// A model of hertz/material, the damping law `law` in the c0 form, no clamp, and the given
/// tangential model; energies off; the history keeps Jian's clock for every law.
vc::ContactModel one_contact_model(int law, double p, double c0, double tau, bool clamp,
                                   double Estar, const vc::TangentialModel &tangential)
{
  vc::ContactModel m;
  m.normal = vc::NormalHertz();
  m.damping.law.law = static_cast<vc::Law>(law);
  m.damping.law.p = p;
  m.damping.law.by_alpha = false;
  m.damping.law.c0 = c0;
  m.damping.law.tau = tau;
  m.damping.law.clamp = clamp;
  m.tangential = tangential;
  m.set_moduli(Estar, 0.0);
  m.track_energy = false;
  vc::HistoryLayout clock;
  clock.damping = 1;
  m.setup(clock);
  return m;
}

/// A contact along n = z with overlap delta, overlap rate ddelta (v_r = vt - ddelta n), no
/// rotation, R* = reff.
vc::ContactGeometry along_z(double delta, double ddelta, const double *vt, double reff, double dt,
                            double t_now)
{
  vc::ContactGeometry g;
  for (int k = 0; k < 3; k++) {
    g.n[k] = k == 2 ? 1.0 : 0.0;
    g.vr[k] = (vt ? vt[k] : 0.0) - (k == 2 ? ddelta : 0.0);
    g.omega_i[k] = g.omega_j[k] = 0.0;
  }
  g.delta = delta;
  g.r_i = g.r_j = 2.0 * reff;
  g.reff = reff;
  g.meff = 1.0;
  g.dt = dt;
  g.t_now = t_now;
  return g;
}
}    // namespace

extern "C" {

/// The normal force F_n = k delta^(3/2) + c0 g(t) delta^p ddelta (unclamped) at n points: the
/// contact model's hertz normal (R* = 1, E* = 3k/4) and damping (law power with exponent p,
/// per-contact k, c0, tau given), the contact begun at time 0 and seen at time t.
void vc_normal_force_many(long n, const double *delta, const double *ddelta, const double *t,
                          const double *k, const double *c0, const double *tau, const double *p,
                          double *out)
{
  for (long i = 0; i < n; ++i) {
    const vc::ContactModel m = one_contact_model(static_cast<int>(vc::Law::Power), p[i], c0[i],
                                                 tau[i], false, 0.75 * k[i], vc::TangentialNone());
    vc::ContactGeometry g = along_z(delta[i], ddelta[i], nullptr, 1.0, 1.0, t[i]);
    const vc::ContactCoeffs cc{k[i], c0[i], tau[i]};
    g.coeffs = &cc;
    double h[64] = {0.0};
    h[0] = 1.0;    // an existing contact, begun at t = 0: its relaxation g(t) as stored
    h[m.history_slots().damping] = vc::relaxation(t[i], tau[i]);
    vc::ContactResult res;
    m.evaluate(g, h, false, res);
    out[i] = res.fn;
  }
}

double vc_relaxation(double t, double tau) { return viscontact::relaxation(t, tau); }

/// The contact model's per-contact coefficients (ContactModel::coeffs) for a damping law given
/// by value: law index (enum order LH Ts KK Li Hunt Jian power), p, by_alpha, alpha, vref,
/// beta, c0, tau, E*; writes k, c0, tau into out[3].
void vc_contact_coeffs(int law, double p, int by_alpha, double alpha, double vref, double beta,
                       double c0, double tau, double Estar, double meff, double reff, double *out)
{
  vc::ContactModel m = one_contact_model(law, p, c0, tau, true, Estar, vc::TangentialNone());
  vc::LawParams &lp = m.damping.law;
  lp.by_alpha = by_alpha != 0;
  lp.alpha = alpha;
  lp.vref = vref;
  lp.beta = beta;
  const vc::ContactCoeffs cc = m.coeffs(meff, reff);
  out[0] = cc.k;
  out[1] = cc.c0;
  out[2] = cc.tau;
}

/// One step of a tangential spring without damping (the contact model's linear_history with
/// KT = kt, XGAMMA 0, MU 1, on a contact whose normal force is fn_limit): xi[3] in/out, n must
/// be z, vtr[3] tangential, dt -> ft[3].
void vc_mindlin(double *xi, const double *n, const double *vtr, double dt, double kt,
                double fn_limit, double *ft)
{
  (void) n;
  vc::TangentialLinearHistory spring;
  spring.kt = kt;
  spring.mu = 1.0;
  // the normal force fn_limit: no overlap, c0 = fn_limit, overlap rate 1 (LH: delta^0 = 1)
  const vc::ContactModel m = one_contact_model(static_cast<int>(vc::Law::LH), 0.0, fn_limit, 0.0,
                                               false, 1.0, spring);
  vc::ContactGeometry g = along_z(0.0, 1.0, vtr, 1.0, dt, 0.0);
  const vc::ContactCoeffs cc{1.0, fn_limit, 0.0};
  g.coeffs = &cc;
  double h[64] = {0.0};
  h[0] = 1.0;
  const int x = m.history_slots().tangential;
  for (int k = 0; k < 3; k++) h[x + k] = xi[k];
  vc::ContactResult res;
  m.evaluate(g, h, true, res);
  for (int k = 0; k < 3; k++) {
    xi[k] = h[x + k];
    ft[k] = res.ft[k];
  }
}

/// The C++ law table, row i (0 <= i < vc_law_count()): name, exponent p (-1: given), whether
/// it needs beta, the history it keeps (comma-separated).
int vc_law_count() { return viscontact::NLAWS; }
const char *vc_law_name(int i) { return viscontact::LAW_TABLE[i].name; }
double vc_law_exponent(int i) { return viscontact::LAW_TABLE[i].p; }
int vc_law_needs_beta(int i) { return viscontact::LAW_TABLE[i].needs_beta ? 1 : 0; }
const char *vc_law_history(int i) { return viscontact::LAW_TABLE[i].history; }

/// THE contact step (ContactModel::evaluate, as pair and wall run it) for one pair contact of
/// a hertz/material normal, a damping law given by c0 (law index in enum order, exponent p, c0,
/// tau, clamp: `end force`) and tangential linear_history KT XGAMMA MU, energies off.
/// geo[18] = n[3] (unit, from j to i), delta, r_i, r_j, m*, v_i - v_j [3], omega_i[3],
/// omega_j[3], dt, t_now.  h: the contact's history (in/out, at least 64 values, zero for a new
/// contact), advanced when advance != 0.  out[8] = F on i [3], torque on i [3], F_n, F_ne.
/// Returns the history size.
int vc_contact_step(int law, double p, double c0, double tau, int clamp, double Estar, double kt,
                    double xgamma, double mu, const double *geo, double *h, int advance,
                    double *out)
{
  vc::TangentialLinearHistory spring;
  spring.kt = kt;
  spring.xgamma = xgamma;
  spring.mu = mu;
  vc::ContactModel m = one_contact_model(law, p, c0, tau, clamp != 0, Estar, spring);
  m.setup();
  vc::ContactGeometry g;
  for (int k = 0; k < 3; k++) {
    g.n[k] = geo[k];
    g.vr[k] = geo[7 + k];
    g.omega_i[k] = geo[10 + k];
    g.omega_j[k] = geo[13 + k];
  }
  g.delta = geo[3];
  g.r_i = geo[4];
  g.r_j = geo[5];
  g.reff = g.r_i * g.r_j / (g.r_i + g.r_j);
  g.meff = geo[6];
  g.dt = geo[16];
  g.t_now = geo[17];
  vc::ContactResult res;
  m.evaluate(g, h, advance != 0, res);
  for (int k = 0; k < 3; k++) {
    out[k] = res.force[k];
    out[3 + k] = res.torque_i[k];
  }
  out[6] = res.fn;
  out[7] = res.fne;
  return m.history_size();
}
}
