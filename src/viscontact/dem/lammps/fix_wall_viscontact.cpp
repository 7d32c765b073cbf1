/* fix viscontact/wall: see fix_wall_viscontact.h for the syntax and the physics.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#include "fix_wall_viscontact.h"

#include "atom.h"
#include "domain.h"
#include "neighbor.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "pair_viscontact.h"
#include "update.h"
#include "utils.h"
#include "viscontact_keywords.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace {
const char *const PREFIX = "fix viscontact/wall: ";
const char *const SYNTAX =
    "fix ID GROUP viscontact/wall (xplane|yplane|zplane LO HI | zcylinder R) "
    "wall_material (E NU | rigid) damping LAW ... tangential (none | mindlin MU) [particle E NU]";

}    // namespace

/* ---------------------------------------------------------------------- */

void FixWallViscontact::fail(const std::string &msg)
{
  error->all(FLERR, std::string(PREFIX) + msg);
}

double FixWallViscontact::parse_coordinate(const std::string &key, const char *text, bool &present)
{
  present = std::strcmp(text, "NULL") != 0;
  if (!present) return 0.0;
  char *end = nullptr;
  const double v = std::strtod(text, &end);
  if (*text == '\0' || *end != '\0' || !std::isfinite(v))
    fail(key + " must be a finite coordinate or NULL, got " + viscontact::quoted(text));
  return v;
}

FixWallViscontact::FixWallViscontact(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), history(nullptr)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("requires atom_style sphere (radius, rmass, omega, torque)");
  if (narg < 4) fail(std::string("missing wall style; usage: ") + SYNTAX);

  // wall geometry
  const std::string style = arg[3];
  int iarg = 4;
  has_lo = has_hi = false;
  lo = hi = cylradius = 0.0;
  if (style == "xplane" || style == "yplane" || style == "zplane") {
    wallstyle = style[0] - 'x';
    nwall = 2;
    if (narg < 6) fail(style + " needs LO HI (a coordinate or NULL each)");
    lo = parse_coordinate(style + " LO", arg[4], has_lo);
    hi = parse_coordinate(style + " HI", arg[5], has_hi);
    if (!has_lo && !has_hi) fail(style + ": LO and HI cannot both be NULL");
    if (has_lo && has_hi && !(lo < hi)) fail(style + ": LO must be below HI");
    const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
    if (periodic[wallstyle]) fail(style + " cannot be used in a periodic dimension");
    iarg = 6;
  } else if (style == "zcylinder") {
    wallstyle = ZCYLINDER;
    nwall = 1;
    if (narg < 5) fail("zcylinder needs its radius R (> 0)");
    const std::string err =
        viscontact::parse_number("zcylinder R", arg[4], viscontact::POSITIVE_DOMAIN, cylradius);
    if (!err.empty()) fail(err);
    if (domain->xperiodic || domain->yperiodic)
      fail("zcylinder cannot be used with periodic x or y");
    iarg = 5;
  } else {
    fail("unknown wall style " + viscontact::quoted(style) +
         "; allowed: xplane yplane zplane (LO HI) or zcylinder R");
  }

  // materials and the law
  std::vector<std::string> args(arg + iarg, arg + narg);
  viscontact::LawKeywords kw;
  bool seen_wall = false;
  has_particle = false;
  wall_rigid = false;
  wall_E = wall_nu = particle_E = particle_nu = 0.0;
  size_t i = 0;
  while (i < args.size()) {
    std::string err;
    if (kw.take(args, i, err)) {
      if (!err.empty()) fail(err);
    } else if (args[i] == "wall_material") {
      if (seen_wall) fail("wall_material given twice");
      seen_wall = true;
      if (i + 1 < args.size() && args[i + 1] == "rigid") {
        wall_rigid = true;
        i += 2;
      } else {
        if (i + 2 >= args.size())
          fail("wall_material needs E NU (E in [1e-10, 1e20], NU in (-1, 0.5]) or rigid");
        err = viscontact::parse_material("wall_material E", "wall_material nu", args[i + 1],
                                         args[i + 2], wall_E, wall_nu);
        if (!err.empty()) fail(err);
        i += 3;
      }
    } else if (args[i] == "particle") {
      if (has_particle) fail("particle given twice");
      if (i + 2 >= args.size()) fail("particle needs E NU (E in [1e-10, 1e20], NU in (-1, 0.5])");
      err = viscontact::parse_material("particle E", "particle nu", args[i + 1], args[i + 2],
                                       particle_E, particle_nu);
      if (!err.empty()) fail(err);
      has_particle = true;
      i += 3;
    } else {
      fail("unknown keyword " + viscontact::quoted(args[i]) +
           "; allowed: wall_material damping end tangential particle");
    }
  }
  if (!seen_wall) fail("missing wall_material (E NU | rigid)");
  const std::string err = kw.finish();
  if (!err.empty()) fail(err);
  law = kw.lp;

  // global output: total force of the wall(s) on the group
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extvector = 1;
  wallforce[0] = wallforce[1] = wallforce[2] = 0.0;
  wallforce_all[0] = wallforce_all[1] = wallforce_all[2] = 0.0;
  wallforce_summed = true;

  // per-atom history: migrates with atoms, goes to restart files
  nvalues = nwall * HIST;
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange = nvalues;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int j = 0; j < atom->nlocal; j++) set_arrays(j);
}

FixWallViscontact::~FixWallViscontact()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(history);
}

int FixWallViscontact::setmask()
{
  return FixConst::POST_FORCE | FixConst::MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixWallViscontact::init()
{
  viscontact::refuse_heat(lmp, "fix viscontact/wall");
  masses.init(lmp, "fix viscontact/wall");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("requires atom_style sphere (radius, rmass, omega, torque)");
  if (utils::strmatch(update->integrate_style, "^respa")) fail("does not support run_style respa");

  // which types of the group are present (any rank): each needs a material
  const int ntypes = atom->ntypes;
  std::vector<int> here(ntypes + 1, 0), present(ntypes + 1, 0);
  for (int j = 0; j < atom->nlocal; j++)
    if (atom->mask[j] & groupbit) here[atom->type[j]] = 1;
  MPI_Allreduce(here.data(), present.data(), ntypes + 1, MPI_INT, MPI_MAX, world);

  auto *pair = dynamic_cast<PairViscontact *>(force->pair_match("viscontact", 1));
  // a rigid wall is an infinitely stiff material: its terms of 1/E* and 1/G* vanish
  const double Ewall = wall_rigid ? INFINITY : wall_E;
  type_law.assign(ntypes + 1, law);
  for (int t = 1; t <= ntypes; t++) {
    double E = particle_E, nu = particle_nu;
    if (!has_particle && !(pair && pair->type_material(t, E, nu))) {
      if (present[t])
        fail("no material for atom type " + std::to_string(t) +
             ": give particle E NU, or pair_style viscontact with pair_coeff " +
             std::to_string(t) + " " + std::to_string(t));
      type_law[t].Estar = type_law[t].Gstar = 0.0;    // an error if it ever touches the wall
      continue;
    }
    type_law[t].Estar = viscontact::mix_Estar(E, nu, Ewall, wall_nu);
    type_law[t].Gstar = viscontact::mix_Gstar(E, nu, Ewall, wall_nu);
  }
  cache.assign(1 << CACHE_BITS, Coeffs());    // the materials may have changed
}

const viscontact::ContactCoeffs &FixWallViscontact::coeffs(int type, double m, double r)
{
  uint64_t bm, br;
  std::memcpy(&bm, &m, sizeof bm);
  std::memcpy(&br, &r, sizeof br);
  const uint64_t key = (bm * 0x9E3779B97F4A7C15ULL) ^ (br * 0xC2B2AE3D27D4EB4FULL) ^
      static_cast<uint64_t>(type) * 0x165667B19E3779F9ULL;
  Coeffs &c = cache[(key * 0xD6E8FEB86659FD93ULL) >> (64 - CACHE_BITS)];
  if (c.type != type || c.m != m || c.r != r) {    // wall: m* = m, r = R* (10.8)
    c.cc = viscontact::contact_coeffs(type_law[type], m, r);
    if (!viscontact::coeffs_finite(c.cc))
      error->one(FLERR, std::string(PREFIX) + "a sphere of type " + std::to_string(type) +
                            " gets " + viscontact::describe_coeffs(c.cc) + "; the values are "
                            "too extreme for its size and mass in this units style");
    c.type = type;
    c.m = m;
    c.r = r;
  }
  return c.cc;
}

void FixWallViscontact::setup(int vflag)
{
  post_force(vflag);
}

void FixWallViscontact::min_setup(int vflag)
{
  post_force(vflag);
}

void FixWallViscontact::min_post_force(int vflag)
{
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   one sphere-wall contact: atom i, wall w, overlap delta > 0, n the unit normal from the wall
   into the sphere.  At setup (update_history false) the history is read, never written.
------------------------------------------------------------------------- */

void FixWallViscontact::contact(int i, int w, double delta, const double n[3], double rwall,
                                bool update_history, double t_now)
{
  double *stored = &history[i][w * HIST];    // touch, xi[3], t0
  double h[HIST];
  for (int m = 0; m < HIST; m++) h[m] = stored[m];
  const double r = atom->radius[i];
  // R* = r rwall/(r + rwall) with the wall's curvature radius rwall (0: a plane, R* = r), as
  // native fix wall/gran (SPEC 10.8); it feeds k_Hertz, a, c0/tau and the Mindlin stiffness
  const double reff = rwall == 0.0 ? r : r * rwall / (r + rwall);
  const double *v = atom->v[i];
  const double *om = atom->omega[i];
  const double dt = update->dt;
  const viscontact::LawParams &lp = type_law[atom->type[i]];
  if (lp.Estar == 0.0)    // a type absent from the group at init (e.g. inserted since)
    error->one(FLERR, std::string(PREFIX) + "no material for atom type " +
                          std::to_string(atom->type[i]) +
                          ": give particle E NU, or pair_coeff I I of pair viscontact");

  double wr[3] = {r * om[0], r * om[1], r * om[2]};
  double vtr[3];
  const double ddelta = -viscontact::relative_tangential_velocity(v, wr, n, vtr);

  if (h[0] == 0.0) {    // a new contact: zero spring, the clock starts now
    h[0] = 1.0;
    h[1] = h[2] = h[3] = 0.0;
    h[4] = viscontact::contact_start_time(t_now, dt, delta, ddelta);
  }
  const viscontact::ContactCoeffs &cc = coeffs(atom->type[i], masses.mass(i, atom->rmass), reff);
  const double fn = viscontact::clamp_normal(
      viscontact::normal_force(delta, ddelta, viscontact::contact_clock(t_now, h[4]), cc.k, cc.c0,
                               cc.tau, lp.p),
      lp.clamp);
  if (!std::isfinite(fn))
    error->one(FLERR, std::string(PREFIX) + "the normal force on atom " +
                          std::to_string(atom->tag[i]) + " is not finite (overlap " +
                          viscontact::format_number(delta) + "); check the time step and the values");

  double ft[3] = {0.0, 0.0, 0.0};
  if (lp.friction) {
    const double kt = viscontact::mindlin_stiffness(lp.Gstar, reff, delta);
    viscontact::mindlin_tangential(&h[1], n, vtr, dt, kt, lp.mu * std::fabs(fn), ft,
                                   update_history);
    double tq[3];
    viscontact::tangential_torque(n, ft, r, tq);
    double *torque = atom->torque[i];
    torque[0] += tq[0];
    torque[1] += tq[1];
    torque[2] += tq[2];
  }
  // a run's setup computes forces from the history but never changes it (as pair viscontact
  // and pair granular): a contact new at setup starts at the first step
  if (update_history)
    for (int m = 0; m < HIST; m++) stored[m] = h[m];
  double *f = atom->f[i];
  for (int d = 0; d < 3; d++) {
    const double fd = fn * n[d] + ft[d];
    f[d] += fd;
    wallforce[d] += fd;
  }
}

void FixWallViscontact::post_force(int /*vflag*/)
{
  const bool update_history = !update->setupflag;
  const double t_now = viscontact::time_now(update);
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;

  wallforce[0] = wallforce[1] = wallforce[2] = 0.0;
  wallforce_summed = false;
  if (neighbor->ago == 0) masses.refresh(atom);    // rigid-body masses of the local atoms

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    for (int w = 0; w < nwall; w++) {
      double n[3] = {0.0, 0.0, 0.0};
      double delta = -1.0;
      double rwall = 0.0;    // a plane
      if (wallstyle == ZCYLINDER) {
        const double rr = std::sqrt(x[i][0] * x[i][0] + x[i][1] * x[i][1]);
        if (rr > 0.0) {
          // as native fix wall/gran: a sphere inside touches a concave wall of curvature
          // radius -2R, one outside the convex outer face, +2R (the overlap and normal of
          // that face)
          const bool inside = rr <= cylradius;
          const double sgn = inside ? -1.0 : 1.0;
          delta = radius[i] - std::fabs(cylradius - rr);
          n[0] = sgn * x[i][0] / rr;
          n[1] = sgn * x[i][1] / rr;
          rwall = 2.0 * sgn * cylradius;
        }
      } else if (w == 0 && has_lo) {
        delta = radius[i] - (x[i][wallstyle] - lo);
        n[wallstyle] = 1.0;
      } else if (w == 1 && has_hi) {
        delta = radius[i] - (hi - x[i][wallstyle]);
        n[wallstyle] = -1.0;
      }
      if (delta > 0.0) {
        contact(i, w, delta, n, rwall, update_history, t_now);
      } else if (update_history) {
        double *h = &history[i][w * HIST];    // contact open: forget it
        for (int m = 0; m < HIST; m++) h[m] = 0.0;
      }
    }
  }
}

double FixWallViscontact::compute_vector(int k)
{
  if (!wallforce_summed) {
    MPI_Allreduce(wallforce, wallforce_all, 3, MPI_DOUBLE, MPI_SUM, world);
    wallforce_summed = true;
  }
  return wallforce_all[k];
}

/* ---- per-atom history: grow, copy, migrate, restart ---------------------------------------- */

void FixWallViscontact::grow_arrays(int nmax)
{
  memory->grow(history, nmax, nvalues, "viscontact/wall:history");
}

void FixWallViscontact::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int m = 0; m < nvalues; m++) history[j][m] = history[i][m];
}

void FixWallViscontact::set_arrays(int i)
{
  for (int m = 0; m < nvalues; m++) history[i][m] = 0.0;
}

int FixWallViscontact::pack_exchange(int i, double *buf)
{
  for (int m = 0; m < nvalues; m++) buf[m] = history[i][m];
  return nvalues;
}

int FixWallViscontact::unpack_exchange(int nlocal, double *buf)
{
  for (int m = 0; m < nvalues; m++) history[nlocal][m] = buf[m];
  return nvalues;
}

int FixWallViscontact::pack_restart(int i, double *buf)
{
  // first value: how many values this fix wrote for the atom, itself included
  buf[0] = nvalues + 1;
  for (int m = 0; m < nvalues; m++) buf[m + 1] = history[i][m];
  return nvalues + 1;
}

void FixWallViscontact::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;    // skip the values of the fixes before this one
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(extra[nlocal][m]) != nvalues + 1)
    error->one(FLERR, std::string(PREFIX) +
                          "restart file holds a different wall history size (was the wall style "
                          "changed between write_restart and read_restart?)");
  m++;
  for (int k = 0; k < nvalues; k++) history[nlocal][k] = extra[nlocal][m++];
}

int FixWallViscontact::size_restart(int /*nlocal*/)
{
  return nvalues + 1;
}

int FixWallViscontact::maxsize_restart()
{
  return nvalues + 1;
}

double FixWallViscontact::memory_usage()
{
  return static_cast<double>(atom->nmax) * nvalues * sizeof(double);
}
