/* pair_style viscontact (see pair_viscontact.h; physics in viscontact_contact.h: Hertz with the
   viscoelastic damping terms of Jian et al., Powder Technol. 356 (2019) 735).
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
    Pair(lmp), models(nullptr), cut_user(nullptr), cut_global(-1.0), dnum(3),
    Ein(nullptr), nuin(nullptr), need_history(0), history_lost(false),
    radii_checked_run{-1, -1}, fix_history(nullptr), heat_on(false)
{
  single_enable = 1;
  // native's 12 (F_t, |F_t|, F_R, |F_R|, tau_twist, x_i - x_j), then the dissipated power and
  // the contact's accumulated dissipated energy
  single_extra = 14;
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
    memory->destroy(cut_user);
    for (int i = 0; i <= atom->ntypes; i++) delete[] models[i];
    delete[] models;
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
  memory->create(cut_user, n + 1, n + 1, "pair:cut_user");
  models = new vc::ContactModel *[n + 1];
  for (int i = 0; i <= n; i++) {
    models[i] = new vc::ContactModel[n + 1];
    for (int j = 0; j <= n; j++) {
      setflag[i][j] = 0;
      Ein[i][j] = nuin[i][j] = 0.0;
      cut_user[i][j] = -1.0;
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
  if (narg > 1)
    fail("pair viscontact: pair_style viscontact takes at most one value, the cutoff CUT (> 0); "
         "without it the cutoff follows the particle sizes, as pair granular's");
  cut_global = -1.0;
  if (narg == 1) {
    const std::string err =
        vc::parse_number("pair_style viscontact CUT", arg[0], vc::POSITIVE_DOMAIN, cut_global);
    if (!err.empty()) fail("pair viscontact: " + err);
  }
}

/* pair_coeff I J NORMAL <keywords> [cutoff C]; the normal model and the law keywords are parsed
   by viscontact_keywords.h, shared with fix viscontact/wall.  Every mistake: one error line
   naming the keyword and what is allowed. */
void PairViscontact::parse_coeff(int narg, char **arg, vc::ContactModel &m, double &E, double &nu,
                                 double &cut)
{
  vc::Args args(arg, arg + narg);
  size_t i = 2;
  std::string err = vc::parse_pair_normal(args, i, m.normal, E, nu);
  if (!err.empty()) fail("pair viscontact: " + err);

  vc::ContactKeywords kw;
  bool seen_cut = false;
  cut = -1.0;
  while (i < args.size()) {
    if (args[i] == "cutoff") {
      if (seen_cut) fail("pair viscontact: cutoff given twice");
      seen_cut = true;
      if (i + 1 >= args.size()) fail("pair viscontact: cutoff needs a value C (> 0)");
      err = vc::parse_number("cutoff C", args[i + 1], vc::POSITIVE_DOMAIN, cut);
      if (!err.empty()) fail("pair viscontact: " + err);
      i += 2;
      continue;
    }
    if (!kw.take(args, i, m, err))
      fail(fmt::format("pair viscontact: unknown keyword {} (allowed after the normal model: "
                       "damping, end, tangential, rolling, twisting, heat, cutoff)",
                       vc::quoted(args[i])) + vc::native_hint(args, i));
    if (!err.empty()) fail("pair viscontact: " + err);
  }
  err = kw.finish(m);
  if (!err.empty()) fail("pair viscontact: " + err);
  m.set_moduli(vc::mix_Estar(E, nu, E, nu), vc::mix_Gstar(E, nu, E, nu));
  m.setup();
}

void PairViscontact::coeff(int narg, char **arg)
{
  if (narg < 2) fail("pair viscontact: pair_coeff needs two atom types");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  vc::ContactModel m;
  double E = 0.0, nu = 0.0, cut = -1.0;
  parse_coeff(narg, arg, m, E, nu, cut);
  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      models[i][j] = models[j][i] = m;
      Ein[i][j] = Ein[j][i] = E;
      nuin[i][j] = nuin[j][i] = nu;
      cut_user[i][j] = cut_user[j][i] = cut;
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

  // heat area: all type pairs or none (as native), per-atom temperature and heatflow
  const int n = atom->ntypes;
  int nheat = 0, nset = 0;
  layout = vc::HistoryLayout();
  // energy bookkeeping (history slots, per-atom tallies) only with a compute viscontact/energy
  energy_on = !modify->get_compute_by_style("^viscontact/energy$").empty();
  for (int i = 1; i <= n; i++)
    for (int j = 1; j <= n; j++) models[i][j].track_energy = energy_on;
  beyond_contact = 0;
  for (int i = 1; i <= n; i++) {
    for (int j = i; j <= n; j++) {
      if (!setflag[i][j]) continue;
      const vc::ContactModel &m = models[i][j];
      nset++;
      if (m.conducts_heat()) nheat++;
      layout.merge(m.layout());
      if (m.beyond_contact()) beyond_contact = 1;
    }
  }
  heat_on = nheat > 0;
  if (heat_on && nheat != nset)
    fail("pair viscontact: heat area must be given for every pair_coeff line or for none");
  if (heat_on && (!atom->temperature_flag || !atom->heatflow_flag))
    fail("pair viscontact: heat area needs per-atom temperature and heatflow (fix property/atom "
         "temperature heatflow, integrated by fix heat/flow)");
  if (!heat_on) viscontact::refuse_heat(lmp, "pair viscontact");
  {
    vc::ContactModel probe;    // the common layout's size
    probe.track_energy = energy_on;
    probe.setup(layout);
    dnum = probe.history_size();
    if (dnum > MAX_HISTORY)    // single()'s copy of a history holds MAX_HISTORY values
      error->all(FLERR, fmt::format("pair viscontact: internal: history of {} values exceeds {}",
                                    dnum, static_cast<int>(MAX_HISTORY)));
  }
  // every type pair in the common layout; the signs of an i <-> j flip from all of them
  hsign.assign(dnum, 1.0);
  for (int i = 1; i <= n; i++) {
    for (int j = 1; j <= n; j++) {
      if (!setflag[i][j]) continue;
      models[i][j].setup(layout);
      models[i][j].history_signs(hsign.data());
    }
  }
  if (history_lost)
    fail("pair viscontact: its contact-history fix " + std::string(HISTORY_ID) + " was deleted "
         "(unfix or plugin unload); give pair_style viscontact and its pair_coeff lines again to "
         "start with fresh contacts");
  masses.init(lmp, "pair viscontact");
  // jkr contacts live beyond r_i + r_j (to the pull-off distance): a size-based list keeps only
  // pairs within r_i + r_j + skin, so use a cutoff list (the cutoffs include the pull-off)
  if (beyond_contact)
    neighbor->add_request(this);
  else
    neighbor->add_request(this, NeighConst::REQ_SIZE);
  coeff_cache.assign(1 << COEFF_CACHE_BITS, CoeffCache());    // coefficients may have changed
  last_coeffs = nullptr;

  // every contact keeps a history (touch flag, start time, dissipated energy, springs)
  need_history = 1;
  if (fix_history && fix_history->history_size() != dnum)
    fail("pair viscontact: the contact history layout changed since the last run (a rolling, "
         "twisting or tangential spring added or removed, or a compute viscontact/energy defined "
         "after the first run); give pair_style viscontact again, or define the compute first");
  if (need_history && fix_history == nullptr) {
    // one fixed ID, so that read_restart re-attaches the per-atom history whatever the
    // instance count of the run that wrote it
    const std::string id = HISTORY_ID;
    Fix *f = modify->get_fix_by_id(id);
    if (!f && modify->get_fix_by_id(DUMMY_ID))
      f = modify->replace_fix(DUMMY_ID, fmt::format("{} all VISCONTACT_HISTORY {}", id, dnum), 1);
    else if (!f)
      f = modify->add_fix(fmt::format("{} all VISCONTACT_HISTORY {}", id, dnum));
    fix_history = dynamic_cast<FixViscontactHistory *>(f);
    if (!fix_history) fail(fmt::format("pair viscontact: fix ID {} is taken by another fix", id));
    if (fix_history->pair && fix_history->pair != this)
      fail("pair viscontact can be used once per simulation (not twice under pair hybrid)");
  }
  if (fix_history) fix_history->pair = this;
  set_cutoff_radii();
}

/* The radii the cutoff must cover (native pair granular's rule, measured on LAMMPS
   22Jul2025): per type, the largest radius that fix pour or fix deposit will insert
   (`extract("radius", type)`; pours first, then deposits, a later positive value overwriting
   an earlier one), raised to the
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

/* Mixing of an unset pair I-J (native pair granular's rules, except G* with NULL KT): the
   sub-model kinds must agree, E* and G* from both materials, every other number the geometric
   mean; then the cutoff (native's automatic rule, extended by jkr's pull-off distance). */
double PairViscontact::init_one(int i, int j)
{
  if (setflag[i][j] == 0) {
    vc::ContactModel m;
    const std::string diff = vc::ContactModel::mix(models[i][i], models[j][j], m);
    if (!diff.empty())
      fail(fmt::format("pair viscontact: types {} and {} use a different {}; give pair_coeff {} {} "
                       "explicitly", i, j, diff, i, j));
    m.set_moduli(vc::mix_Estar(Ein[i][i], nuin[i][i], Ein[j][j], nuin[j][j]),
                 vc::mix_Gstar(Ein[i][i], nuin[i][i], Ein[j][j], nuin[j][j]));
    m.setup(layout);
    models[i][j] = m;
    cut_user[i][j] = MAX(cut_user[i][i], cut_user[j][j]);
  }
  models[j][i] = models[i][j];
  cut_user[j][i] = cut_user[i][j];

  if (cut_user[i][j] > 0.0) return cut_user[i][j];
  if (cut_global > 0.0) return cut_global;
  // cutoff: the reach of the largest spheres that can meet (native pair granular's rule)
  const vc::ContactModel &m = models[i][j];
  auto reach = [&m](double r1, double r2) {
    return r1 + r2 + m.pulloff_distance(r1 * r2 / (r1 + r2));
  };
  const std::vector<double> &d = maxrad_dynamic, &f = maxrad_frozen;
  if ((d[i] > 0.0 && d[j] > 0.0) || (d[i] > 0.0 && f[j] > 0.0) || (f[i] > 0.0 && d[j] > 0.0)) {
    double cut = 0.0;
    if (d[i] > 0.0 && d[j] > 0.0) cut = MAX(cut, reach(d[i], d[j]));
    if (f[i] > 0.0 && d[j] > 0.0) cut = MAX(cut, reach(f[i], d[j]));
    if (d[i] > 0.0 && f[j] > 0.0) cut = MAX(cut, reach(d[i], f[j]));
    return cut;
  }
  // no sphere of i or j yet, nor announced: the largest of all, so that binning never sees 0
  double cut = 0.0;
  for (int t = 1; t <= atom->ntypes; t++) cut = MAX(cut, 2.0 * MAX(d[t], f[t]));
  return cut;
}

/* The geometry and kinematics of the pair (i, j), dx = x_i - x_j, for the contact step at time
   t_now with time step dt (read from update once per force call: stores to the forces and
   histories could alias update's doubles, so a read per contact would be a load per contact). */
VISCONTACT_ALWAYS_INLINE void PairViscontact::pair_geometry(int i, int j, const double dx[3], double rsq, double meff,
                                   double dt, double t_now, vc::ContactGeometry &g) const
{
  double **v = atom->v, **omega = atom->omega;
  const double radi = atom->radius[i], radj = atom->radius[j];
  const double r = std::sqrt(rsq), rinv = 1.0 / r;
  for (int k = 0; k < 3; k++) {
    g.n[k] = dx[k] * rinv;
    g.vr[k] = v[i][k] - v[j][k];
    g.omega_i[k] = omega[i][k];
    g.omega_j[k] = omega[j][k];
  }
  g.delta = radi + radj - r;
  g.r_i = radi;
  g.r_j = radj;
  g.reff = radi * radj / (radi + radj);
  g.meff = meff;
  g.dt = dt;
  g.t_now = t_now;
  g.wall = false;
  g.coeffs = nullptr;
  if (heat_on) {
    g.T_i = atom->temperature[i];
    g.T_j = atom->temperature[j];
  }
}

/* Per-contact k_H, c0, tau depend on (types, m*, R*) only: a small direct-mapped cache saves
   the powers of the alpha form for the few distinct contacts of most packings. */
const vc::ContactCoeffs &PairViscontact::coeffs_lookup(int i, int j, int itype, int jtype,
                                                       double meff, double reff)
{
  uint64_t bm, br;
  std::memcpy(&bm, &meff, sizeof bm);
  std::memcpy(&br, &reff, sizeof br);
  const uint64_t h = (bm ^ (br * 0x9E3779B97F4A7C15ULL) ^ ((uint64_t) (itype * 131 + jtype)
                      * 0xC2B2AE3D27D4EB4FULL)) * 0x165667B19E3779F9ULL;
  CoeffCache &e = coeff_cache[h >> (64 - COEFF_CACHE_BITS)];
  if (e.itype != itype || e.jtype != jtype || e.meff != meff || e.reff != reff) {
    e.cc = models[itype][jtype].coeffs(meff, reff);
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
  vc::relaxation_step(e.cc, update->dt);
  last_coeffs = &e;
  return e.cc;
}

/* At each neighbour-list build and at the first step of a run (`run ... pre no` builds
   nothing): the radii against the cutoff; at each build, the rigid-body masses. */
void PairViscontact::refresh_atoms()
{
  if (neighbor->ago == 0 || update->firststep != radii_checked_run[0] ||
      update->laststep != radii_checked_run[1]) {
    check_radii();
    radii_checked_run[0] = update->firststep;
    radii_checked_run[1] = update->laststep;
  }
  if (neighbor->ago == 0 && masses.refresh(atom)) {
    masses.grow(atom->nmax);
    comm->forward_comm(this);
  }
}

/* One contact's force, torques and heat flow to i and (both_sides) to j (f, torque, heatflow:
   the atoms' arrays, read once per force call). */
VISCONTACT_ALWAYS_INLINE void PairViscontact::apply(double **f, double **torque, double *heatflow,
                                                    int i, int j, bool both_sides,
                                                    const vc::ContactResult &res)
{
  const double *F = res.force;
  f[i][0] += F[0];
  f[i][1] += F[1];
  f[i][2] += F[2];
  torque[i][0] += res.torque_i[0];
  torque[i][1] += res.torque_i[1];
  torque[i][2] += res.torque_i[2];
  if (heatflow) heatflow[i] += res.heat;
  if (both_sides) {
    f[j][0] -= F[0];
    f[j][1] -= F[1];
    f[j][2] -= F[2];
    torque[j][0] += res.torque_j[0];
    torque[j][1] += res.torque_j[1];
    torque[j][2] += res.torque_j[2];
    if (heatflow) heatflow[j] -= res.heat;
  }
}

void PairViscontact::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);

  double **x = atom->x, **f = atom->f, **torque = atom->torque;
  const double *radius = atom->radius, *rmass = atom->rmass;
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;
  // forces of a run's setup must not advance the history (as pair granular)
  const bool history_update = !update->setupflag;
  FixViscontactHistory *fh = (fix_history && fix_history->ready()) ? fix_history : nullptr;
  if (!fh) fail("pair viscontact: contact history is not set up (internal error)");
  const int *mask = atom->mask;
  refresh_atoms();
  double *heatflow = heat_on ? atom->heatflow : nullptr;
  EnergyTally *tally = energy_begin();
  const double *special_lj = force->special_lj;
  const bool t0_convert = t0_restart;
  const double dt = update->dt, t_now = vc::time_now(update);

  const int inum = list->inum;
  const int *ilist = list->ilist, *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const int itype = type[i];
    const double radi = radius[i];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    char *fl = fh->flags_of(i);
    double *hv = fh->values_of(i);

    for (int jj = 0; jj < jnum; jj++) {
      // bonded partners (special_bonds): as pair granular, a factor 0 skips the pair (its
      // history is left as it is), another factor scales its forces, torques and energies (not
      // its heat flow)
      const double factor_lj = special_lj[sbmask(jlist[jj])];
      if (factor_lj == 0.0) continue;
      const int j = jlist[jj] & NEIGHMASK;
      const int jtype = type[j];
      const double radj = radius[j];
      const double dx[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
      const double rsq = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
      const double radsum = radi + radj;
      double *h = &hv[(size_t) dnum * jj];
      const vc::ContactModel &m = models[itype][jtype];
      // apart: r >= r_i + r_j, unless a jkr contact lives on to its pull-off distance
      if (rsq >= radsum * radsum &&
          !(beyond_contact && fl[jj] && m.touching(rsq, radsum, radi * radj / radsum, true))) {
        // apart (jkr: beyond pull-off): the contact (if any) has ended, in a run's setup too
        // (native); a new one starts afresh
        if (fl[jj]) {
          if (tally && history_update) {
            // the last forces' second half-work, on this step's velocities
            vc::ContactGeometry now;
            pair_geometry(i, j, dx, rsq, masses.pair_meff(i, j, rmass, mask), dt, t_now, now);
            tally->add_release(i, j, nlocal, newton_pair, m, h, factor_lj, &now);
          }
          fl[jj] = 0;
          for (int k = 0; k < dnum; k++) h[k] = 0.0;
        }
        continue;
      }
      // (g and res are this contact's alone, their addresses never taken: the compiler keeps
      // them in registers and folds g.wall)
      vc::ContactGeometry g;
      vc::ContactResult res;
      pair_geometry(i, j, dx, rsq, masses.pair_meff(i, j, rmass, mask), dt, t_now, g);
      g.coeffs = &coeffs_of(i, j, itype, jtype, g.meff, g.reff, dt);
      // a contact begins (its history is initialised) when first found touching, in a run's
      // setup too, and keeps what setup writes (the Coulomb caps): native pair granular marks
      // it touching there, so a jkr contact stretched in the first step keeps its attraction
      if (!fl[jj]) h[0] = 0.0;
      else if (t0_convert) m.relaxation_from_start_time(h, *g.coeffs, g.t_now);
      m.evaluate(g, h, history_update, res);
      fl[jj] = 1;
      if (factor_lj != 1.0) res.scale(factor_lj);
      if (!std::isfinite(res.fn))
        error->one(FLERR, fmt::format("pair viscontact: the normal force between atoms {} and {} "
                   "is not finite (overlap {}); check the time step and the pair_coeff values",
                   atom->tag[i], atom->tag[j], g.delta));

      apply(f, torque, heatflow, i, j, newton_pair || j < nlocal, res);
      // (a run's setup: its elastic energies only, the state the run starts from)
      if (tally) tally->add_pair(i, j, nlocal, newton_pair, res);
      if (evflag)
        ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, res.force[0], res.force[1], res.force[2],
                     dx[0], dx[1], dx[2]);
    }
  }
  if (tally) energy_end(tally, history_update);
  t0_restart = false;    // converted in the first force call after read_restart
}

/* One pair for compute pair/local: returns 0 (no energy), fforce = F_ne / r (the elastic normal
   force, as native), svector = F_t (3), |F_t|, F_R (3), |F_R|, twisting torque, x_i - x_j (3),
   the dissipated power, the contact's accumulated dissipated energy.  The history is used as
   stored (not advanced). */
double PairViscontact::single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/,
                              double factor_lj, double &fforce)
{
  for (int k = 0; k < single_extra; k++) svector[k] = 0.0;
  fforce = 0.0;
  if (factor_lj == 0.0) return 0.0;    // a bonded pair that compute() skips
  double **x = atom->x;
  const double radi = atom->radius[i], radj = atom->radius[j];
  const double radsum = radi + radj;
  const vc::ContactModel &m = models[itype][jtype];

  // this contact's history in the pair's neighbour list (i's entry for j), if any
  double hist[MAX_HISTORY] = {0.0};
  bool touched = false;
  if (fix_history && fix_history->ready()) {
    const int *jlist = list->firstneigh[i];
    const int jnum = list->numneigh[i];
    const char *fl = fix_history->flags_of(i);
    const double *hv = fix_history->values_of(i);
    for (int jj = 0; jj < jnum; jj++) {
      if ((jlist[jj] & NEIGHMASK) == j && fl[jj]) {
        for (int k = 0; k < dnum; k++) hist[k] = hv[(size_t) dnum * jj + k];
        touched = true;
        break;
      }
    }
  }
  if (!m.touching(rsq, radsum, radi * radj / radsum, touched)) return 0.0;
  const double dx[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
  vc::ContactGeometry g;
  vc::ContactResult res;
  pair_geometry(i, j, dx, rsq, masses.pair_meff(i, j, atom->rmass, atom->mask), update->dt,
                vc::time_now(update), g);
  const int es = m.history_slots().energy;
  const double stored = es >= 0 ? hist[es] : 0.0;
  m.evaluate(g, hist, false, res);
  if (factor_lj != 1.0) res.scale(factor_lj);    // the special_bonds factor, as compute()
  fforce = res.fn / std::sqrt(rsq);    // the whole normal force (elastic + damping), as native
  for (int k = 0; k < 3; k++) {
    svector[k] = res.ft[k];
    svector[4 + k] = res.fr[k];
    svector[9 + k] = dx[k];
  }
  svector[3] = std::sqrt(res.ft[0] * res.ft[0] + res.ft[1] * res.ft[1] + res.ft[2] * res.ft[2]);
  svector[7] = std::sqrt(res.fr[0] * res.fr[0] + res.fr[1] * res.fr[1] + res.fr[2] * res.fr[2]);
  svector[8] = res.tau_twist;
  svector[12] = res.power;
  svector[13] = factor_lj * stored;    // the history accumulates the unscaled energy
  return 0.0;
}

/* ---- restart: per set type pair E, nu, the cutoff and the sub-models' records (by name, with
   their coefficients and versions, viscontact_submodel.h); format 2 (the 30 values of
   viscontact 2026-11, f0c8c3f) is still read ---- */

static constexpr int RESTART_VERSION = 3;
static constexpr int NRESTART_V2 = 30;

/* Format 2's 30 values of one type pair as the sub-models' records (the kinds' enum orders
   then are the variants' orders now). */
static std::vector<vc::Record> records_v2(const double *b)
{
  auto rec = [](const auto *kind, const char *name, int index, std::vector<double> values) {
    const std::vector<std::string> names = vc::alternative_names(kind);
    const std::string alt = index >= 0 && index < (int) names.size() ? names[index] : "?";
    return vc::Record{std::string(name) + " " + alt, 1, std::move(values)};
  };
  const int normal = (int) b[13], tang = (int) b[15], roll = (int) b[20], twist = (int) b[24];
  const std::vector<double> none;
  std::vector<vc::Record> r;
  r.push_back(rec((vc::NormalModel *) nullptr, "normal", normal, normal ? std::vector<double>{b[14]} : none));
  r.push_back({std::string("damping ") + vc::law_name(static_cast<vc::Law>((int) b[0])), 1,
               {b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8]}});
  r.push_back(rec((vc::TangentialModel *) nullptr, "tangential", tang,
                  tang == 0 ? none : tang == 1 ? std::vector<double>{b[18], b[19]}
                                               : std::vector<double>{b[16], b[17], b[18], b[19]}));
  r.push_back(rec((vc::RollingModel *) nullptr, "rolling", roll, roll ? std::vector<double>{b[21], b[22], b[23]} : none));
  r.push_back(rec((vc::TwistingModel *) nullptr, "twisting", twist,
                  twist == 2 ? std::vector<double>{b[25], b[26], b[27]} : none));
  r.push_back(rec((vc::HeatModel *) nullptr, "heat", (int) b[28], b[28] != 0.0 ? std::vector<double>{b[29]} : none));
  return r;
}

void PairViscontact::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (!setflag[i][j]) continue;
      const double head[3] = {Ein[i][j], nuin[i][j], cut_user[i][j]};
      fwrite(head, sizeof(double), 3, fp);
      vc::RecordWriter w;
      for (const vc::Record &r : models[i][j].records()) w.add(r);
      const int nbytes = static_cast<int>(w.bytes.size());
      fwrite(&nbytes, sizeof(int), 1, fp);
      fwrite(w.bytes.data(), 1, w.bytes.size(), fp);
    }
  }
}

/* One set type pair's record of format 3 (rank 0 reads, all get it): E, nu, cutoff, records. */
std::vector<vc::Record> PairViscontact::read_pair_record(FILE *fp, double head[3])
{
  const int me = comm->me;
  int nbytes = 0;
  if (me == 0) {
    utils::sfread(FLERR, head, sizeof(double), 3, fp, nullptr, error);
    utils::sfread(FLERR, &nbytes, sizeof(int), 1, fp, nullptr, error);
  }
  MPI_Bcast(head, 3, MPI_DOUBLE, 0, world);
  MPI_Bcast(&nbytes, 1, MPI_INT, 0, world);
  std::vector<char> bytes(nbytes > 0 ? nbytes : 0);
  if (me == 0 && nbytes > 0) utils::sfread(FLERR, bytes.data(), 1, nbytes, fp, nullptr, error);
  if (nbytes > 0) MPI_Bcast(bytes.data(), nbytes, MPI_CHAR, 0, world);
  std::vector<vc::Record> records;
  vc::RecordReader reader(bytes.data(), bytes.size());
  vc::Record r;
  while (reader.next(r)) records.push_back(r);
  return records;
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
      if (!setflag[i][j]) continue;
      double head[3];
      std::vector<vc::Record> records;
      if (restart_format == 2) {
        double buf[NRESTART_V2 + 1];
        if (me == 0) utils::sfread(FLERR, buf, sizeof(double), NRESTART_V2 + 1, fp, nullptr, error);
        MPI_Bcast(buf, NRESTART_V2 + 1, MPI_DOUBLE, 0, world);
        records = records_v2(buf);
        head[0] = buf[11];
        head[1] = buf[12];
        head[2] = buf[NRESTART_V2];
      } else {
        records = read_pair_record(fp, head);
      }
      vc::ContactModel m;
      const std::string err = m.from_records(records);
      if (!err.empty())
        fail(fmt::format("pair viscontact: type pair {} {} of the restart file: {}", i, j, err));
      Ein[i][j] = Ein[j][i] = head[0];
      nuin[i][j] = nuin[j][i] = head[1];
      m.set_moduli(vc::mix_Estar(head[0], head[1], head[0], head[1]),
                   vc::mix_Gstar(head[0], head[1], head[0], head[1]));
      m.setup();
      models[i][j] = models[j][i] = m;
      cut_user[i][j] = cut_user[j][i] = head[2];
    }
  }
}

/* The format version and the global cutoff. */
void PairViscontact::write_restart_settings(FILE *fp)
{
  const int version = RESTART_VERSION;
  fwrite(&version, sizeof(int), 1, fp);
  fwrite(&cut_global, sizeof(double), 1, fp);
}

void PairViscontact::read_restart_settings(FILE *fp)
{
  int version = 0;
  if (comm->me == 0) utils::sfread(FLERR, &version, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&version, 1, MPI_INT, 0, world);
  if (version != 2 && version != RESTART_VERSION)
    fail(fmt::format("pair viscontact: this restart file holds contact model format {}; this "
                     "viscontact reads formats 2 and {}: give pair_style viscontact and its "
                     "pair_coeff lines again after read_restart", version, RESTART_VERSION));
  restart_format = version;
  t0_restart = version == 2;
  if (comm->me == 0) utils::sfread(FLERR, &cut_global, sizeof(double), 1, fp, nullptr, error);
  MPI_Bcast(&cut_global, 1, MPI_DOUBLE, 0, world);
}

/* ---- energy accounting (on when a compute viscontact/energy asks for it) ---- */

PairViscontact::EnergyTally *PairViscontact::energy_begin()
{
  if (!energy_requested || !energy_on) return nullptr;
  const int nall = atom->nlocal + atom->nghost;
  tally_.diss.assign((size_t) nall * vc::NDISS, 0.0);
  tally_.elastic.assign((size_t) nall * vc::NELASTIC, 0.0);
  return &tally_;
}

void PairViscontact::EnergyTally::add_pair(int i, int j, int nlocal, int newton_pair,
                                           const vc::ContactResult &r)
{
  for (int side = 0; side < 2; side++) {
    const int a = side ? j : i;
    if (side && !(newton_pair || j < nlocal)) break;
    for (int k = 0; k < vc::NDISS; k++) diss[(size_t) a * vc::NDISS + k] += 0.5 * r.dissipated[k];
    for (int k = 0; k < vc::NELASTIC; k++)
      elastic[(size_t) a * vc::NELASTIC + k] += 0.5 * r.elastic[k];
  }
}

void PairViscontact::EnergyTally::add_release(int i, int j, int nlocal, int newton_pair,
                                               const vc::ContactModel &m, const double *h,
                                               double factor, const vc::ContactGeometry *now)
{
  double d[vc::NDISS] = {0.0};
  m.release(h, d, now);
  for (double &x : d) x *= factor;
  for (int side = 0; side < 2; side++) {
    const int a = side ? j : i;
    if (side && !(newton_pair || j < nlocal)) break;
    for (int k = 0; k < vc::NDISS; k++) diss[(size_t) a * vc::NDISS + k] += 0.5 * d[k];
  }
}

void PairViscontact::energy_end(EnergyTally *t, bool advance)
{
  if (force->newton_pair) {
    comm_reverse = vc::NDISS + vc::NELASTIC;
    comm->reverse_comm(this);
  }
  fix_history->add_energy(t->diss.data(), t->elastic.data(), advance);
}

int PairViscontact::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    for (int k = 0; k < vc::NDISS; k++) buf[m++] = tally_.diss[(size_t) i * vc::NDISS + k];
    for (int k = 0; k < vc::NELASTIC; k++) buf[m++] = tally_.elastic[(size_t) i * vc::NELASTIC + k];
  }
  return m;
}

void PairViscontact::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int i = list[k];
    for (int c = 0; c < vc::NDISS; c++) tally_.diss[(size_t) i * vc::NDISS + c] += buf[m++];
    for (int c = 0; c < vc::NELASTIC; c++) tally_.elastic[(size_t) i * vc::NELASTIC + c] += buf[m++];
  }
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
  return n * n * (sizeof(vc::ContactModel) + 3 * sizeof(double) + sizeof(int) + sizeof(double)) +
      (double) (tally_.diss.capacity() + tally_.elastic.capacity()) * sizeof(double);
}
