/* pair_style viscontact (see pair_viscontact.h; physics in viscontact_contact.h, SPEC section 9).
   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */

#include "pair_viscontact.h"
#include "viscontact_keywords.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_viscontact_history.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>

using namespace LAMMPS_NS;
namespace vc = viscontact;

static const char *const HISTORY_ID = "VISCONTACT_HISTORY";
static const char *const DUMMY_ID = "VISCONTACT_HISTORY_DUMMY";

PairViscontact::PairViscontact(LAMMPS *lmp) :
    Pair(lmp), params(nullptr), Ein(nullptr), nuin(nullptr), need_history(0),
    history_lost(false), radii_checked_run{-1, -1}, fix_history(nullptr)
{
  single_enable = 1;
  single_extra = 4;    // F_t (x, y, z) and the overlap, for compute pair/local p1..p4
  svector = new double[single_extra];
  restartinfo = 1;
  finitecutflag = 1;
  beyond_contact = 0;
  no_virial_fdotr_compute = 1;
  comm_forward = 1;    // rigid-body masses of ghost atoms
  // a placeholder at this point of the fix list (replaced by the history fix in init_style), so
  // the history fix comes before fixes defined later that migrate atoms (fix balance)
  if (domain->box_exist && !modify->get_fix_by_id(HISTORY_ID) && !modify->get_fix_by_id(DUMMY_ID))
    modify->add_fix(std::string(DUMMY_ID) + " all DUMMY");
}

PairViscontact::~PairViscontact()
{
  if (copymode) return;
  delete[] svector;
  svector = nullptr;
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(Ein);
    memory->destroy(nuin);
    for (int i = 0; i <= atom->ntypes; i++) delete[] params[i];
    delete[] params;
  }
  if (fix_history && modify->get_fix_by_id(HISTORY_ID)) {
    fix_history->pair = nullptr;    // no call back into this half-destroyed pair
    modify->delete_fix(HISTORY_ID);
  }
  if (modify->get_fix_by_id(DUMMY_ID)) modify->delete_fix(DUMMY_ID);
}

void PairViscontact::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(Ein, n + 1, n + 1, "pair:Ein");
  memory->create(nuin, n + 1, n + 1, "pair:nuin");
  params = new vc::LawParams *[n + 1];
  for (int i = 0; i <= n; i++) {
    params[i] = new vc::LawParams[n + 1];
    for (int j = 0; j <= n; j++) {
      setflag[i][j] = 0;
      Ein[i][j] = nuin[i][j] = 0.0;
    }
  }
  maxrad_dynamic.assign(n + 1, 0.0);
  maxrad_frozen.assign(n + 1, 0.0);
}

void PairViscontact::fail(const std::string &msg)
{
  error->all(FLERR, msg);
  std::abort();    // not reached: error->all does not return
}

void PairViscontact::settings(int narg, char **arg)
{
  history_lost = false;    // a new pair_style line: the next init starts a fresh history fix
  if (narg > 0)
    fail(fmt::format("pair viscontact: pair_style viscontact takes no options, got {} (the "
                     "cutoff follows the particle sizes, as pair granular's)", vc::quoted(arg[0])));
}

/* pair_coeff I J hertz/material E NU <law keywords>; the law keywords (damping LAW [p P] FORM
   [end force|overlap] tangential TANG) are parsed by viscontact_keywords.h, shared with fix
   viscontact/wall.  Every mistake: one error line naming the keyword and what is allowed. */
void PairViscontact::parse_coeff(int narg, char **arg, vc::LawParams &lp, double &E, double &nu)
{
  std::vector<std::string> args(arg, arg + narg);
  if (narg < 3 || args[2] != "hertz/material")
    fail(fmt::format("pair viscontact: expected 'hertz/material E NU' after the two types, got "
                     "{}", vc::quoted(narg < 3 ? "" : arg[2])));
  if (narg < 5) fail("pair viscontact: hertz/material needs two values, E and NU");
  std::string err = vc::parse_material("E", "nu", args[3], args[4], E, nu);
  if (!err.empty()) fail("pair viscontact: " + err);

  vc::LawKeywords kw;
  size_t i = 5;
  while (i < args.size()) {
    if (!kw.take(args, i, err))
      fail(fmt::format("pair viscontact: unknown keyword {} (allowed after hertz/material E NU: "
                       "damping LAW [p P] alpha A vref V [beta B] | c0 C [tau S], end force|overlap, "
                       "tangential none|mindlin MU)", vc::quoted(args[i])));
    if (!err.empty()) fail("pair viscontact: " + err);
  }
  err = kw.finish();
  if (!err.empty()) fail("pair viscontact: " + err);
  lp = kw.lp;
  lp.Estar = vc::mix_Estar(E, nu, E, nu);
  lp.Gstar = vc::mix_Gstar(E, nu, E, nu);
}

void PairViscontact::coeff(int narg, char **arg)
{
  if (narg < 2) fail("pair viscontact: pair_coeff needs two atom types");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  vc::LawParams lp;
  double E = 0.0, nu = 0.0;
  parse_coeff(narg, arg, lp, E, nu);
  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      params[i][j] = params[j][i] = lp;
      Ein[i][j] = Ein[j][i] = E;
      nuin[i][j] = nuin[j][i] = nu;
      setflag[i][j] = 1;
      count++;
    }
  }
  if (count == 0) fail("pair viscontact: pair_coeff selects no type pair");
}

bool PairViscontact::type_material(int itype, double &E, double &nu) const
{
  if (!allocated || itype < 1 || itype > atom->ntypes || !setflag[itype][itype]) return false;
  E = Ein[itype][itype];
  nu = nuin[itype][itype];
  return true;
}

void PairViscontact::init_style()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("pair viscontact requires atom_style sphere (per-atom radius, rmass, omega, torque)");
  if (comm->ghost_velocity == 0) fail("pair viscontact requires 'comm_modify vel yes'");

  viscontact::refuse_heat(lmp, "pair viscontact");
  if (history_lost)
    fail("pair viscontact: its contact-history fix " + std::string(HISTORY_ID) + " was deleted "
         "(unfix or plugin unload); give pair_style viscontact and its pair_coeff lines again to "
         "start with fresh contacts");
  masses.init(lmp, "pair viscontact");
  neighbor->add_request(this, NeighConst::REQ_SIZE);
  coeff_cache.assign(1 << COEFF_CACHE_BITS, CoeffCache());    // coefficients may have changed

  // history is needed for friction and Jian's clock
  need_history = 0;
  const int n = atom->ntypes;
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++)
      if (setflag[i][j] && (params[i][j].friction || params[i][j].law == vc::Law::Jian))
        need_history = 1;
  if (need_history && fix_history == nullptr) {
    // one fixed ID, so that read_restart re-attaches the per-atom history whatever the
    // instance count of the run that wrote it
    const std::string id = HISTORY_ID;
    Fix *f = modify->get_fix_by_id(id);
    if (!f && modify->get_fix_by_id(DUMMY_ID))
      f = modify->replace_fix(DUMMY_ID, id + " all VISCONTACT_HISTORY", 1);
    else if (!f)
      f = modify->add_fix(id + " all VISCONTACT_HISTORY");
    fix_history = dynamic_cast<FixViscontactHistory *>(f);
    if (!fix_history) fail(fmt::format("pair viscontact: fix ID {} is taken by another fix", id));
    if (fix_history->pair && fix_history->pair != this)
      fail("pair viscontact can be used once per simulation (not twice under pair hybrid)");
  }
  if (fix_history) fix_history->pair = this;
  set_cutoff_radii();
}

/* The radii the cutoff must cover (SPEC 10.7, native pair granular's rule): per type, the
   largest radius that fix pour or fix deposit will insert (`extract("radius", type)`; pours
   first, then deposits, a later positive value overwriting an earlier one), raised to the
   largest radius of the moving atoms present; separately the largest radius of frozen atoms
   (fix freeze).  Maxima over all ranks. */
void PairViscontact::set_cutoff_radii()
{
  const int n = atom->ntypes;
  std::vector<double> dyn(n + 1, 0.0), frz(n + 1, 0.0);
  std::vector<Fix *> inserters = modify->get_fix_by_style("^pour");
  for (Fix *f : modify->get_fix_by_style("^deposit")) inserters.push_back(f);
  for (Fix *f : inserters) {
    for (int t = 1; t <= n; t++) {
      int itype = t;
      const auto *r = static_cast<const double *>(f->extract("radius", itype));
      if (r && *r > 0.0) dyn[t] = *r;
    }
  }
  const double *radius = atom->radius;
  const int *type = atom->type, *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++) {
    std::vector<double> &slot = (mask[i] & masses.freeze_bit) ? frz : dyn;
    slot[type[i]] = MAX(slot[type[i]], radius[i]);
  }
  maxrad_dynamic.assign(n + 1, 0.0);
  maxrad_frozen.assign(n + 1, 0.0);
  MPI_Allreduce(dyn.data(), maxrad_dynamic.data(), n + 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(frz.data(), maxrad_frozen.data(), n + 1, MPI_DOUBLE, MPI_MAX, world);
}

/* A sphere larger than its type's radius in the cutoff (grown by `set ... diameter` before a
   `run ... pre no`, fix adapt, or an insertion fix that does not report its radius) could miss
   contacts with ghost atoms: stop instead (checked at each neighbour-list build). */
void PairViscontact::check_radii() const
{
  const double *radius = atom->radius;
  const int *type = atom->type, *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++) {
    const int t = type[i];
    const double limit = (mask[i] & masses.freeze_bit) ? MAX(maxrad_dynamic[t], maxrad_frozen[t])
                                                      : maxrad_dynamic[t];
    if (radius[i] > limit)
      error->one(FLERR, fmt::format("pair viscontact: atom {} (type {}) has radius {} but the "
                                    "interaction cutoff was set at the last run's start for at "
                                    "most {}; start a new run (not 'pre no') after changing sizes, "
                                    "or insert with fix pour or fix deposit", atom->tag[i], t,
                                    radius[i], limit));
  }
}

double PairViscontact::init_one(int i, int j)
{
  if (setflag[i][j] == 0) {
    const vc::LawParams &a = params[i][i], &b = params[j][j];
    if (a.law != b.law || a.p != b.p || a.by_alpha != b.by_alpha || a.friction != b.friction)
      fail(fmt::format("pair viscontact: types {} and {} use different laws; give pair_coeff {} {} "
                       "explicitly", i, j, i, j));
    vc::LawParams m = a;
    auto geo = [](double x, double y) { return std::sqrt(x * y); };
    m.alpha = geo(a.alpha, b.alpha);
    m.vref = geo(a.vref, b.vref);
    m.beta = geo(a.beta, b.beta);
    m.c0 = geo(a.c0, b.c0);
    m.tau = geo(a.tau, b.tau);
    m.mu = geo(a.mu, b.mu);
    m.clamp = a.clamp || b.clamp;    // native: the larger limit_damping
    m.Estar = vc::mix_Estar(Ein[i][i], nuin[i][i], Ein[j][j], nuin[j][j]);
    m.Gstar = vc::mix_Gstar(Ein[i][i], nuin[i][i], Ein[j][j], nuin[j][j]);
    params[i][j] = m;
  }
  params[j][i] = params[i][j];

  // cutoff: the contact distance of the largest spheres that can meet (SPEC 10.7)
  const std::vector<double> &d = maxrad_dynamic, &f = maxrad_frozen;
  if ((d[i] > 0.0 && d[j] > 0.0) || (d[i] > 0.0 && f[j] > 0.0) || (f[i] > 0.0 && d[j] > 0.0))
    return MAX(d[i] + d[j], MAX(f[i] + d[j], d[i] + f[j]));
  // no sphere of i or j yet, nor announced: the largest of all, so that binning never sees 0
  double cut = 0.0;
  for (int t = 1; t <= atom->ntypes; t++) cut = MAX(cut, 2.0 * MAX(d[t], f[t]));
  return cut;
}

namespace {
/* The geometry and kinematics of one touching sphere pair (i, j), shared by compute() and
   single(): dx = x_i - x_j with rsq = |dx|^2 < (r_i + r_j)^2. */
struct PairContact {
  double r, rinv, delta;   // distance, 1 / distance, overlap r_i + r_j - r [m]
  double n[3];             // unit normal from j to i
  double vtr[3];           // relative tangential velocity of the contact point [m/s]
  double ddelta;           // overlap rate (> 0 approaching) [m/s]
  double meff, reff;       // m* [kg], R* [m]
};

inline PairContact pair_contact(const double dx[3], double rsq, double radi, double radj,
                                const double vi[3], const double vj[3], const double wi[3],
                                const double wj[3], double meff)
{
  PairContact c;
  const double radsum = radi + radj;
  c.r = std::sqrt(rsq);
  c.rinv = 1.0 / c.r;
  c.delta = radsum - c.r;
  for (int k = 0; k < 3; k++) c.n[k] = dx[k] * c.rinv;
  const double vr[3] = {vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]};
  const double wr[3] = {radi * wi[0] + radj * wj[0], radi * wi[1] + radj * wj[1],
                        radi * wi[2] + radj * wj[2]};
  c.ddelta = -vc::relative_tangential_velocity(vr, wr, c.n, c.vtr);
  c.meff = meff;
  c.reff = radi * radj / radsum;
  return c;
}

}    // namespace

void PairViscontact::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);

  double **x = atom->x, **v = atom->v, **f = atom->f;
  double **omega = atom->omega, **torque = atom->torque;
  const double *radius = atom->radius, *rmass = atom->rmass;
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  const double dt = update->dt;
  const double t_now = vc::time_now(update);
  // forces of a run's setup must not advance the history (as pair granular)
  const bool history_update = !update->setupflag;
  FixViscontactHistory *fh = (fix_history && fix_history->ready()) ? fix_history : nullptr;
  if (need_history && !fh) fail("pair viscontact: contact history is not set up (internal error)");
  const int *mask = atom->mask;
  if (neighbor->ago == 0 || update->firststep != radii_checked_run[0] ||
      update->laststep != radii_checked_run[1]) {
    // at each build, and at the first step of a run (`run ... pre no` builds nothing)
    check_radii();
    radii_checked_run[0] = update->firststep;
    radii_checked_run[1] = update->laststep;
  }
  if (neighbor->ago == 0) {
    if (masses.refresh(atom)) {
      masses.grow(atom->nmax);
      comm->forward_comm(this);
    }
  }

  vc::ContactCoeffs cc{0.0, 0.0, 0.0};

  const int inum = list->inum;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int itype = type[i];
    const double radi = radius[i];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    char *fl = fh ? fh->flags_of(i) : nullptr;
    double *hv = fh ? fh->values_of(i) : nullptr;

    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const int jtype = type[j];
      const double radj = radius[j];
      const double dx[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      const double rsq = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
      const double radsum = radi + radj;
      double *h = hv ? &hv[vc::HISTORY_SIZE * jj] : nullptr;
      if (rsq >= radsum * radsum) {
        // apart: the contact (if any) has ended; a new one starts afresh
        if (fl && history_update && fl[jj]) {
          fl[jj] = 0;
          for (int k = 0; k < vc::HISTORY_SIZE; k++) h[k] = 0.0;
        }
        continue;
      }
      const vc::LawParams &lp = params[itype][jtype];
      const PairContact c = pair_contact(dx, rsq, radi, radj, v[i], v[j], omega[i], omega[j],
                                         masses.pair_meff(i, j, rmass, mask));
      const double delta = c.delta, ddelta = c.ddelta, meff = c.meff, reff = c.reff;
      const double *n = c.n, *vtr = c.vtr;
      {
        // per-contact coefficients depend on (types, m*, R*) only: a small direct-mapped cache
        // saves the powers of the alpha form for the few distinct contacts of most packings
        uint64_t bm, br;
        std::memcpy(&bm, &meff, sizeof bm);
        std::memcpy(&br, &reff, sizeof br);
        const uint64_t h = (bm ^ (br * 0x9E3779B97F4A7C15ULL) ^ ((uint64_t) (itype * 131 + jtype)
                            * 0xC2B2AE3D27D4EB4FULL)) * 0x165667B19E3779F9ULL;
        CoeffCache &e = coeff_cache[h >> (64 - COEFF_CACHE_BITS)];
        if (e.itype != itype || e.jtype != jtype || e.meff != meff || e.reff != reff) {
          e.cc = vc::contact_coeffs(lp, meff, reff);
          if (!vc::coeffs_finite(e.cc))
            error->one(FLERR, fmt::format("pair viscontact: the contact of atoms {} and {} (types "
                       "{} {}) has {}; the pair_coeff values are too extreme for these sizes and "
                       "masses in this units style", atom->tag[i], atom->tag[j], itype, jtype,
                       vc::describe_coeffs(e.cc)));
          e.itype = itype;
          e.jtype = jtype;
          e.meff = meff;
          e.reff = reff;
        }
        cc = e.cc;
      }

      // history: this step's copy (written back only outside a run's setup)
      double local[vc::HISTORY_SIZE] = {0.0, 0.0, 0.0, t_now};
      double *hc = local;
      if (h) {
        if (fl[jj]) {
          for (int k = 0; k < vc::HISTORY_SIZE; k++) local[k] = h[k];
        } else {
          local[3] = vc::contact_start_time(t_now, dt, delta, ddelta);
        }
        if (history_update) {
          for (int k = 0; k < vc::HISTORY_SIZE; k++) h[k] = local[k];
          fl[jj] = 1;
          hc = h;
        }
      }
      // >= 0 even if the user resets the simulation time (reset_timestep ... time) mid-contact
      const double t_contact = vc::contact_clock(t_now, hc[3]);

      const double fn = vc::clamp_normal(
          vc::normal_force(delta, ddelta, t_contact, cc.k, cc.c0, cc.tau, lp.p), lp.clamp);
      if (!std::isfinite(fn))
        error->one(FLERR, fmt::format("pair viscontact: the normal force between atoms {} and {} "
                   "is not finite (overlap {}, rate {}); check the time step and the pair_coeff "
                   "values", atom->tag[i], atom->tag[j], delta, ddelta));
      double ft[3] = {0.0, 0.0, 0.0};
      if (lp.friction) {
        const double kt = vc::mindlin_stiffness(lp.Gstar, reff, delta);
        vc::mindlin_tangential(hc, n, vtr, dt, kt, lp.mu * std::fabs(fn), ft, history_update);
      }

      const double fx = fn * n[0] + ft[0];
      const double fy = fn * n[1] + ft[1];
      const double fz = fn * n[2] + ft[2];
      double ti[3], tj[3];
      vc::tangential_torque(n, ft, radi - 0.5 * delta, ti);
      f[i][0] += fx;
      f[i][1] += fy;
      f[i][2] += fz;
      torque[i][0] += ti[0];
      torque[i][1] += ti[1];
      torque[i][2] += ti[2];
      if (newton_pair || j < nlocal) {
        vc::tangential_torque(n, ft, radj - 0.5 * delta, tj);
        f[j][0] -= fx;
        f[j][1] -= fy;
        f[j][2] -= fz;
        torque[j][0] += tj[0];
        torque[j][1] += tj[1];
        torque[j][2] += tj[2];
      }
      if (evflag) ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, fx, fy, fz, dx[0], dx[1], dx[2]);
    }
  }
}

/* One pair's forces for compute pair/local: returns 0 (no energy), fforce = F_n / r (so that
   "force" = F_n, the clamped normal force), svector = F_t on i (x, y, z) and the overlap.  The
   tangential force comes from the stored history as it is (not advanced). */
double PairViscontact::single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/,
                              double /*factor_lj*/, double &fforce)
{
  for (int k = 0; k < single_extra; k++) svector[k] = 0.0;
  fforce = 0.0;
  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  const double radi = atom->radius[i], radj = atom->radius[j];
  const double radsum = radi + radj;
  if (rsq >= radsum * radsum) return 0.0;
  const vc::LawParams &lp = params[itype][jtype];
  const double dx[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
  const PairContact c = pair_contact(dx, rsq, radi, radj, v[i], v[j], omega[i], omega[j],
                                     masses.pair_meff(i, j, atom->rmass, atom->mask));
  const double delta = c.delta, ddelta = c.ddelta, reff = c.reff, rinv = c.rinv;
  const double *n = c.n, *vtr = c.vtr;
  const vc::ContactCoeffs cc = vc::contact_coeffs(lp, c.meff, reff);
  const double dt = update->dt;
  const double t_now = vc::time_now(update);

  // this contact's history in the pair's neighbour list (i's entry for j), if any
  double hist[vc::HISTORY_SIZE] = {0.0, 0.0, 0.0, vc::contact_start_time(t_now, dt, delta, ddelta)};
  if (fix_history && fix_history->ready()) {
    const int *jlist = list->firstneigh[i];
    const int jnum = list->numneigh[i];
    const char *fl = fix_history->flags_of(i);
    const double *hv = fix_history->values_of(i);
    for (int jj = 0; jj < jnum; jj++) {
      if ((jlist[jj] & NEIGHMASK) == j && fl[jj]) {
        for (int k = 0; k < vc::HISTORY_SIZE; k++) hist[k] = hv[vc::HISTORY_SIZE * jj + k];
        break;
      }
    }
  }
  const double fn = vc::clamp_normal(
      vc::normal_force(delta, ddelta, vc::contact_clock(t_now, hist[3]), cc.k, cc.c0, cc.tau, lp.p),
      lp.clamp);
  double ft[3] = {0.0, 0.0, 0.0};
  if (lp.friction)
    vc::mindlin_tangential(hist, n, vtr, dt, vc::mindlin_stiffness(lp.Gstar, reff, delta),
                           lp.mu * std::fabs(fn), ft, false);
  fforce = fn * rinv;
  svector[0] = ft[0];
  svector[1] = ft[1];
  svector[2] = ft[2];
  svector[3] = delta;
  return 0.0;
}

/* ---- restart: the coefficients as given, per set type pair ---- */

static constexpr int NRESTART = 13;

void PairViscontact::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) {
        const vc::LawParams &lp = params[i][j];
        const double buf[NRESTART] = {(double) static_cast<int>(lp.law), lp.p,
                                      lp.by_alpha ? 1.0 : 0.0, lp.alpha, lp.vref, lp.beta, lp.c0,
                                      lp.tau, lp.clamp ? 1.0 : 0.0, lp.friction ? 1.0 : 0.0,
                                      lp.mu, Ein[i][j], nuin[i][j]};
        fwrite(buf, sizeof(double), NRESTART, fp);
      }
    }
  }
}

void PairViscontact::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        double buf[NRESTART];
        if (me == 0) utils::sfread(FLERR, buf, sizeof(double), NRESTART, fp, nullptr, error);
        MPI_Bcast(buf, NRESTART, MPI_DOUBLE, 0, world);
        vc::LawParams lp;
        lp.law = static_cast<vc::Law>((int) buf[0]);
        lp.p = buf[1];
        lp.by_alpha = buf[2] != 0.0;
        lp.alpha = buf[3];
        lp.vref = buf[4];
        lp.beta = buf[5];
        lp.c0 = buf[6];
        lp.tau = buf[7];
        lp.clamp = buf[8] != 0.0;
        lp.friction = buf[9] != 0.0;
        lp.mu = buf[10];
        Ein[i][j] = Ein[j][i] = buf[11];
        nuin[i][j] = nuin[j][i] = buf[12];
        lp.Estar = vc::mix_Estar(buf[11], buf[12], buf[11], buf[12]);
        lp.Gstar = vc::mix_Gstar(buf[11], buf[12], buf[11], buf[12]);
        params[i][j] = params[j][i] = lp;
      }
    }
  }
}

/* One int (0), kept so that restart files of earlier versions stay readable. */
void PairViscontact::write_restart_settings(FILE *fp)
{
  const int reserved = 0;
  fwrite(&reserved, sizeof(int), 1, fp);
}

void PairViscontact::read_restart_settings(FILE *fp)
{
  int reserved = 0;
  if (comm->me == 0) utils::sfread(FLERR, &reserved, sizeof(int), 1, fp, nullptr, error);
}

/* Rigid-body masses to ghost atoms (EffectiveMass). */
int PairViscontact::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  for (int k = 0; k < n; k++) buf[k] = masses.body_mass[list[k]];
  return n;
}

void PairViscontact::unpack_forward_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) masses.body_mass[first + k] = buf[k];
}

double PairViscontact::memory_usage()
{
  const double n = atom->ntypes + 1;
  return n * n * (sizeof(vc::LawParams) + 2 * sizeof(double) + sizeof(int) + sizeof(double));
}
