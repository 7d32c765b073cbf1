/* extern "C" entry points to viscontact_contact.h for the ctypes tests
   (tests/dem/pair/test_cpp_kernel.py).  Built by viscontact.dem.plugin.kernel_library_path()
   into a tiny library of its own: no LAMMPS. */
#include "viscontact_contact.h"
#include "viscontact_model.h"

extern "C" {

/// normal_force for n points (arrays of length n), results into out.
void vc_normal_force_many(long n, const double *delta, const double *ddelta, const double *t,
                          const double *k, const double *c0, const double *tau, const double *p,
                          double *out)
{
  for (long i = 0; i < n; ++i)
    out[i] = viscontact::normal_force(delta[i], ddelta[i], t[i], k[i], c0[i], tau[i], p[i]);
}

double vc_relaxation(double t, double tau) { return viscontact::relaxation(t, tau); }

/// contact_coeffs for one LawParams given by value: law index (enum order LH Ts KK Li Hunt Jian
/// power), p, by_alpha, alpha, vref, beta, c0, tau, E*; writes k, c0, tau into out[3].
void vc_contact_coeffs(int law, double p, int by_alpha, double alpha, double vref, double beta,
                       double c0, double tau, double Estar, double meff, double reff, double *out)
{
  viscontact::LawParams lp;
  lp.law = static_cast<viscontact::Law>(law);
  lp.p = p;
  lp.by_alpha = by_alpha != 0;
  lp.alpha = alpha;
  lp.vref = vref;
  lp.beta = beta;
  lp.c0 = c0;
  lp.tau = tau;
  lp.Estar = Estar;
  const viscontact::ContactCoeffs cc = viscontact::contact_coeffs(lp, meff, reff);
  out[0] = cc.k;
  out[1] = cc.c0;
  out[2] = cc.tau;
}

/// one Mindlin step: xi[3] in/out, n[3], vtr[3], dt, kt, fn_limit -> ft[3]
void vc_mindlin(double *xi, const double *n, const double *vtr, double dt, double kt,
                double fn_limit, double *ft)
{
  viscontact::mindlin_tangential(xi, n, vtr, dt, kt, fn_limit, ft);
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
  viscontact::ContactModel m;
  m.normal.kind = viscontact::NormalKind::Hertz;
  m.law.law = static_cast<viscontact::Law>(law);
  m.law.p = p;
  m.law.by_alpha = false;
  m.law.c0 = c0;
  m.law.tau = tau;
  m.law.clamp = clamp != 0;
  m.law.Estar = Estar;
  m.tangential.kind = viscontact::TangentialKind::LinearHistory;
  m.tangential.kt = kt;
  m.tangential.xgamma = xgamma;
  m.tangential.mu = mu;
  m.track_energy = false;
  m.setup();
  viscontact::ContactGeometry g;
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
  viscontact::ContactResult res;
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
