/* fix viscontact/wall: see fix_wall_viscontact.h for the syntax and the physics.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#include "fix_wall_viscontact.h"

#include "atom.h"
#include "domain.h"
#include "neighbor.h"
#include "error.h"
#include "force.h"
#include "input.h"
#include "variable.h"
#include "memory.h"
#include "modify.h"
#include "pair_viscontact.h"
#include "region.h"
#include "comm.h"
#include "update.h"
#include "utils.h"
#include "viscontact_keywords.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace {
const char *const PREFIX = "fix viscontact/wall: ";
const char *const SYNTAX =
    "fix ID GROUP viscontact/wall (xplane|yplane|zplane LO HI | zcylinder R | region ID | "
    "mesh FILE ...) "
    "wall_material (E NU | rigid) damping LAW ... tangential ... [wiggle DIM A PERIOD | "
    "shear DIM V] [particle E NU] [contacts]";
const char *const KEYWORDS =
    "wall_material normal damping end tangential rolling twisting heat temperature wiggle shear "
    "particle contacts";
constexpr double BIG = 1.0e300;    // distance to an absent (NULL) plane
const viscontact::Domain ANY_NUMBER{-1e300, 1e300, false};    // wiggle A, shear V

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

int FixWallViscontact::parse_dim(const std::string &key, const std::string &text)
{
  if (text == "x") return 0;
  if (text == "y") return 1;
  if (text == "z") return 2;
  fail(key + " DIM must be x, y or z, got " + viscontact::quoted(text));
}

/* The wall style and its values (arg[3] on); returns the index of the first keyword after them. */
int FixWallViscontact::parse_wall(int narg, char **arg)
{
  const std::string style = arg[3];
  int iarg = 4;
  has_lo = has_hi = false;
  lo = hi = cylradius = 0.0;
  if (style == "xplane" || style == "yplane" || style == "zplane") {
    wallstyle = style[0] - 'x';
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
    if (narg < 5) fail("zcylinder needs its radius R (> 0)");
    const std::string err =
        viscontact::parse_number("zcylinder R", arg[4], viscontact::POSITIVE_DOMAIN, cylradius);
    if (!err.empty()) fail(err);
    if (domain->xperiodic || domain->yperiodic)
      fail("zcylinder cannot be used with periodic x or y");
    iarg = 5;
  } else if (style == "region") {
    wallstyle = REGION;
    if (narg < 5) fail("region needs the ID of a region");
    idregion = arg[4];
    region = domain->get_region_by_id(idregion);
    if (!region) fail("region " + viscontact::quoted(idregion) + " does not exist");
    tmax = region->tmax;
    if (tmax < 1) fail("region " + viscontact::quoted(idregion) + " has no surface to touch");
    iarg = 5;
  } else if (style == "mesh") {
    wallstyle = MESH;
    iarg = mesh_parse(narg, arg, 4);
  } else {
    fail("unknown wall style " + viscontact::quoted(style) +
         "; allowed: xplane yplane zplane (LO HI), zcylinder R, region REGION-ID or mesh FILE");
  }

  return iarg;
}

/* `wiggle DIM A PERIOD` or `shear DIM V` at args[i]; returns the index after it. */
size_t FixWallViscontact::parse_motion(const std::vector<std::string> &args, size_t i)
{
  std::string err;
  const bool wiggle = args[i] == "wiggle";
  if (motion == (wiggle ? WIGGLE : SHEAR)) fail(args[i] + " given twice");
  if (motion != STILL) fail("wiggle and shear cannot be combined: choose one");
  if (!wiggle) {
    if (i + 2 >= args.size()) fail("shear needs DIM V (DIM x|y|z, V a velocity)");
    axis = parse_dim("shear", args[i + 1]);
    err = viscontact::parse_number("shear V", args[i + 2], ANY_NUMBER, vshear);
    if (!err.empty()) fail(err);
    motion = SHEAR;
    return i + 3;
  }
  if (i + 3 >= args.size()) fail("wiggle needs DIM A PERIOD (DIM x|y|z, PERIOD > 0)");
  axis = parse_dim("wiggle", args[i + 1]);
  double period = 0.0;
  err = viscontact::parse_number("wiggle A", args[i + 2], ANY_NUMBER, amplitude);
  if (err.empty())
    err = viscontact::parse_number("wiggle PERIOD", args[i + 3], viscontact::POSITIVE_DOMAIN,
                                   period);
  if (!err.empty()) fail(err);
  wfreq = 2.0 * M_PI / period;
  motion = WIGGLE;
  return i + 4;
}

/* The keywords after the wall (materials, motion, the contact model, outputs). */
void FixWallViscontact::parse_keywords(const std::vector<std::string> &args)
{
  viscontact::ContactKeywords kw;
  bool seen_normal = false;
  bool seen_wall = false;
  has_particle = false;
  wall_rigid = false;
  wall_E = wall_nu = particle_E = particle_nu = 0.0;
  motion = STILL;
  axis = 0;
  amplitude = wfreq = vshear = 0.0;
  peratom_flag = 0;
  has_twall = false;
  twall = 0.0;
  tvar = -1;
  size_t i = 0;
  while (i < args.size()) {
    std::string err;
    if (kw.take(args, i, model, err)) {
      if (!err.empty()) fail(err);
    } else if (args[i] == "normal") {
      if (seen_normal) fail("normal given twice");
      seen_normal = true;
      err = viscontact::parse_wall_normal(args, i, model.normal);
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
    } else if (args[i] == "wiggle" || args[i] == "shear") {
      i = parse_motion(args, i);
    } else if (args[i] == "temperature") {
      if (has_twall) fail("temperature given twice");
      if (i + 1 >= args.size())
        fail("temperature needs the wall temperature T or v_NAME (an equal-style variable)");
      if (args[i + 1].compare(0, 2, "v_") == 0 && args[i + 1].size() > 2) {
        tstr = args[i + 1].substr(2);
      } else {
        err = viscontact::parse_number("temperature T", args[i + 1],
                                       viscontact::Domain{0.0, 1e300, false}, twall);
        if (!err.empty()) fail(err);
      }
      has_twall = true;
      i += 2;
    } else if (args[i] == "contacts") {
      if (peratom_flag) fail("contacts given twice");
      peratom_flag = 1;
      size_peratom_cols = 8;
      peratom_freq = 1;
      i += 1;
    } else {
      fail("unknown keyword " + viscontact::quoted(args[i]) + "; allowed: " + KEYWORDS +
           viscontact::native_hint(args, i));
    }
  }
  if (!seen_wall) fail("missing wall_material (E NU | rigid)");
  const std::string err = kw.finish(model);
  if (!err.empty()) fail(err);
  model.setup();
  heat_on = model.conducts_heat();
  if (heat_on && !has_twall)
    fail("heat area needs the wall temperature: temperature T or temperature v_NAME");
  if (!heat_on && has_twall) fail("temperature is only used with heat area K");
}

FixWallViscontact::FixWallViscontact(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), region(nullptr), tmax(1), store(nullptr), nstored(nullptr),
    energy_on(false), ediss(nullptr), eel(nullptr), heat_on(false)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("requires atom_style sphere (radius, rmass, omega, torque)");
  if (narg < 4) fail(std::string("missing wall style; usage: ") + SYNTAX);

  const int iarg = parse_wall(narg, arg);
  parse_keywords(std::vector<std::string>(arg + iarg, arg + narg));
  const std::string style = arg[3];

  if (motion != STILL) {
    const char *what = motion == WIGGLE ? "wiggle" : "shear";
    if (wallstyle == MESH)
      fail(std::string(what) + " cannot be used with a mesh wall: move the mesh with its move "
                               "and rotate keywords");
    if (wallstyle == REGION)
      fail(std::string(what) + " cannot be used with a region wall: move the region itself "
                               "(region ... move/rotate)");
    if (motion == WIGGLE && wallstyle == ZCYLINDER && axis != 2)
      fail("zcylinder can only wiggle along z");
    if (motion == SHEAR && wallstyle == axis)
      fail(std::string("shear DIM must lie in the plane (") + style + " cannot shear along " +
           "xyz"[axis] + ")");
  }
  time_origin = update->ntimestep;

  // global output: total force of the wall(s) on the group
  vector_flag = 1;
  if (wallstyle != MESH) size_vector = 3;    // a mesh: 6, force and torque (mesh_parse)
  global_freq = 1;
  extvector = 1;
  wallforce[0] = wallforce[1] = wallforce[2] = 0.0;
  wallforce_all[0] = wallforce_all[1] = wallforce_all[2] = 0.0;
  wallforce_summed = true;

  // per-atom history: migrates with atoms, goes to restart files; the global record keeps a
  // region's motion and the wiggle origin
  hsize = model.history_size();
  slotsize = 1 + hsize;
  nvalues = 1 + tmax * slotsize;
  goes_on.assign(tmax, 0);
  fresh.assign(tmax, 0);
  restart_peratom = 1;
  restart_global = 1;
  create_attribute = 1;
  maxexchange = nvalues + viscontact::NDISS + (peratom_flag ? size_peratom_cols : 0);
  array_atom = nullptr;
  touches.reserve(tmax);
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int j = 0; j < atom->nlocal; j++) set_arrays(j);
}

FixWallViscontact::~FixWallViscontact()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(store);
  memory->destroy(nstored);
  memory->destroy(array_atom);
  memory->destroy(ediss);
  memory->destroy(eel);
  mesh_free();
}

int FixWallViscontact::setmask()
{
  return FixConst::POST_FORCE | FixConst::MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixWallViscontact::init()
{
  if (heat_on) {
    if (!atom->temperature_flag || !atom->heatflow_flag)
      fail("heat area needs per-atom temperature and heatflow (fix property/atom temperature "
           "heatflow, integrated by fix heat/flow)");
  } else {
    viscontact::refuse_heat(lmp, "fix viscontact/wall");
  }
  masses.init(lmp, "fix viscontact/wall");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    fail("requires atom_style sphere (radius, rmass, omega, torque)");
  if (utils::strmatch(update->integrate_style, "^respa")) fail("does not support run_style respa");
  if (!tstr.empty()) {
    tvar = input->variable->find(tstr.c_str());
    if (tvar < 0) fail("temperature variable " + viscontact::quoted(tstr) + " does not exist");
    if (!input->variable->equalstyle(tvar))
      fail("temperature variable " + viscontact::quoted(tstr) + " must be equal-style");
  }
  if (wallstyle == MESH) mesh_init();
  if (wallstyle == REGION) {
    region = domain->get_region_by_id(idregion);
    if (!region) fail("region " + viscontact::quoted(idregion) + " does not exist");
    if (region->tmax > tmax)
      fail("region " + viscontact::quoted(idregion) + " was redefined with more faces than "
           "when the fix was defined: define the fix again");
  }

  energy_on = !modify->get_compute_by_style("^viscontact/energy$").empty();

  // which types of the group are present (any rank): each needs a material
  const int ntypes = atom->ntypes;
  std::vector<int> here(ntypes + 1, 0), present(ntypes + 1, 0);
  for (int j = 0; j < atom->nlocal; j++)
    if (atom->mask[j] & groupbit) here[atom->type[j]] = 1;
  MPI_Allreduce(here.data(), present.data(), ntypes + 1, MPI_INT, MPI_MAX, world);

  auto *pair = dynamic_cast<PairViscontact *>(force->pair_match("viscontact", 1));
  // a rigid wall is an infinitely stiff material: its terms of 1/E* and 1/G* vanish
  const double Ewall = wall_rigid ? INFINITY : wall_E;
  type_model.assign(ntypes + 1, model);
  type_ok.assign(ntypes + 1, 0);
  for (int t = 1; t <= ntypes; t++) {
    double E = particle_E, nu = particle_nu;
    if (!has_particle && !(pair && pair->type_material(t, E, nu))) {
      if (present[t])
        fail("no material for atom type " + std::to_string(t) +
             ": give particle E NU, or pair_style viscontact with pair_coeff " +
             std::to_string(t) + " " + std::to_string(t));
      continue;    // an error if it ever touches the wall
    }
    type_model[t].set_moduli(viscontact::mix_Estar(E, nu, Ewall, wall_nu),
                             viscontact::mix_Gstar(E, nu, Ewall, wall_nu));
    type_model[t].setup();
    // the energy bookkeeping only with a compute viscontact/energy (as pair viscontact); its
    // history slots stay in the layout either way (restart files and migration unchanged)
    type_model[t].track_energy = energy_on;
    type_ok[t] = 1;
  }
  cache.assign(1 << CACHE_BITS, Coeffs());    // the materials may have changed
  last_coeffs = nullptr;
}

const viscontact::ContactCoeffs &FixWallViscontact::coeffs_lookup(int type, double m, double r)
{
  uint64_t bm, br;
  std::memcpy(&bm, &m, sizeof bm);
  std::memcpy(&br, &r, sizeof br);
  const uint64_t key = (bm * 0x9E3779B97F4A7C15ULL) ^ (br * 0xC2B2AE3D27D4EB4FULL) ^
      static_cast<uint64_t>(type) * 0x165667B19E3779F9ULL;
  Coeffs &c = cache[(key * 0xD6E8FEB86659FD93ULL) >> (64 - CACHE_BITS)];
  if (c.type != type || c.m != m || c.r != r) {    // wall: m* = m, r = R* (10.8)
    c.cc = type_model[type].coeffs(m, r);
    if (!viscontact::coeffs_finite(c.cc))
      error->one(FLERR, std::string(PREFIX) + "a sphere of type " + std::to_string(type) +
                            " gets " + viscontact::describe_coeffs(c.cc) + "; the values are "
                            "too extreme for its size and mass in this units style");
    c.type = type;
    c.m = m;
    c.r = r;
  }
  viscontact::relaxation_step(c.cc, update->dt);
  last_coeffs = &c;
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
   the wall faces near sphere i: planes and cylinder as LAMMPS fix wall/gran (the nearer plane
   of LO/HI; the cylinder's +-2R curvature), a region through Region::surface().  Planes and
   the cylinder reach out to a jkr contact's pull-off distance (whether a face touches is the
   contact model's decision, with the face's touch flag); a region reaches the sphere radius
   only (as native: region jkr contacts end at zero overlap).
------------------------------------------------------------------------- */

// (no SLP vectorization: it read a face's contact vector, just stored by the region's search
// as separate doubles, as one 16-byte pair, which cannot be forwarded from the store buffer
// and stalled every atom's search: the turning drum 0.92 -> 0.85 x native's time)
VISCONTACT_NO_SLP void FixWallViscontact::find_touches(int i, double wlo, double whi,
                                                       const double vplane[3])
{
  touches.clear();
  const double *x = atom->x[i];
  const double rad = atom->radius[i];
  const viscontact::ContactModel &m = type_model[atom->type[i]];
  Touch c;
  c.rwall = 0.0;
  c.n[0] = c.n[1] = c.n[2] = 0.0;
  c.vwall[0] = vplane[0];
  c.vwall[1] = vplane[1];
  c.vwall[2] = vplane[2];
  if (wallstyle <= ZPLANE) {
    const int d = wallstyle;
    const double del1 = has_lo ? x[d] - wlo : BIG;
    const double del2 = has_hi ? whi - x[d] : BIG;
    // signed distance from the nearer plane (a sphere pushed through it has the normal
    // reversed, as in LAMMPS)
    const double dist = del1 < del2 ? del1 : -del2;
    c.iwall = del1 < del2 ? 0 : 1;
    c.r = std::fabs(dist);
    if (c.r >= rad + m.pulloff_distance(rad) || c.r == 0.0) return;
    c.n[d] = dist > 0.0 ? 1.0 : -1.0;
    touches.push_back(c);
  } else if (wallstyle == ZCYLINDER) {
    const double delxy = std::sqrt(x[0] * x[0] + x[1] * x[1]);
    const double delr = cylradius - delxy;
    c.iwall = 0;
    c.r = std::fabs(delr);
    // as native: a sphere inside touches a concave wall of curvature radius -2R, one outside
    // the convex outer face, +2R
    c.rwall = delxy < cylradius ? -2.0 * cylradius : 2.0 * cylradius;
    const double reach = rad + m.pulloff_distance(effective_radius(rad, c.rwall));
    if (delr > rad || c.r >= reach || c.r == 0.0 || delxy == 0.0) return;
    // n from the surface into the sphere: inwards for a sphere inside, outwards outside
    const double s = delr > 0.0 ? -1.0 : 1.0;
    c.n[0] = s * x[0] / delxy;
    c.n[1] = s * x[1] / delxy;
    if (motion == SHEAR && axis != 2) {    // a turning cylinder, surface speed V
      c.vwall[0] = vshear * x[1] / delxy;
      c.vwall[1] = -vshear * x[0] / delxy;
      c.vwall[2] = 0.0;
    }
    touches.push_back(c);
  } else if (wallstyle == MESH) {
    mesh_touches(i);
  } else {
    const int nc = region_surface(x, rad);
    if (nc > tmax)
      error->one(FLERR, std::string(PREFIX) + "atom " + std::to_string(atom->tag[i]) +
                            " touches " + std::to_string(nc) + " faces of region " + idregion +
                            ", more than the " + std::to_string(tmax) + " it allows");
    const bool moving = region_moving;
    for (int ic = 0; ic < nc; ic++) {
      const auto &rc = region->contact[ic];
      if (!(rc.r > 0.0) || rc.r >= rad) continue;
      c.iwall = rc.iwall;
      c.r = rc.r;
      const double rinv = 1.0 / rc.r;    // one division, not three
      c.n[0] = rc.delx * rinv;
      c.n[1] = rc.dely * rinv;
      c.n[2] = rc.delz * rinv;
      c.rwall = rc.radius;
      if (moving) {
        // translation, rotation, then a face whose size changes in time: the shape's rate of
        // change at the contact point xc, for every such region.  (Region::velocity_contact()
        // sets xc only for a rotating region but hands it to the shape term in any case:
        // native fix wall/gran/region gets no shape velocity on a region that does not rotate.)
        double xc[3] = {x[0] - rc.delx, x[1] - rc.dely, x[2] - rc.delz};
        frame.velocity(xc, c.vwall);
        if (region->varshape && rc.varflag) region->velocity_contact_shape(c.vwall, xc);
      } else {
        c.vwall[0] = c.vwall[1] = c.vwall[2] = 0.0;
      }
      touches.push_back(c);
    }
  }
}

/* ----------------------------------------------------------------------
   one sphere-wall contact through the one contact step (ContactModel::evaluate): atom i, the
   contact's history h (updated in place), the face c.  Adds force, torque, heat flow and
   energy to atom i.
------------------------------------------------------------------------- */

VISCONTACT_ALWAYS_INLINE void FixWallViscontact::contact(int i, double *h, const Touch &c,
                                                         bool update_history, double dt,
                                                         double t_now)
{
  const int type = atom->type[i];
  const viscontact::ContactModel &m = type_model[type];
  const double r = atom->radius[i];
  viscontact::ContactGeometry g;
  for (int d = 0; d < 3; d++) {
    g.n[d] = c.n[d];
    g.vr[d] = atom->v[i][d] - c.vwall[d];
    g.omega_i[d] = atom->omega[i][d];
    g.omega_j[d] = 0.0;
  }
  g.delta = r - c.r;
  g.r_i = r;
  g.r_j = 0.0;
  // R* = r rw/(r + rw) with the wall's signed curvature radius rw (0: flat, R* = r), as
  // native fix wall/gran(/region); m* = m (or the rigid body's mass)
  g.reff = effective_radius(r, c.rwall);
  g.meff = masses.mass(i, atom->rmass);
  g.dt = dt;
  g.t_now = t_now;
  if (heat_on) {
    g.T_i = atom->temperature[i];
    g.T_j = twall;
  }
  g.wall = true;
  g.coeffs = &coeffs(type, g.meff, g.reff);
  if (t0_restart && h[0] != 0.0) m.relaxation_from_start_time(h, *g.coeffs, t_now);

  viscontact::ContactResult res;
  m.evaluate(g, h, update_history, res);
  if (!std::isfinite(res.fn) || !std::isfinite(res.force[0]) || !std::isfinite(res.force[1]) ||
      !std::isfinite(res.force[2]))
    error->one(FLERR, std::string(PREFIX) + "the force on atom " + std::to_string(atom->tag[i]) +
                          " is not finite (overlap " + viscontact::format_number(g.delta) +
                          "); check the time step and the values");

  double *f = atom->f[i];
  double *torque = atom->torque[i];
  for (int d = 0; d < 3; d++) {
    f[d] += res.force[d];
    torque[d] += res.torque_i[d];
    wallforce[d] += res.force[d];
  }
  if (meshwall) mesh_tally(i, c, res.force);
  if (heat_on) atom->heatflow[i] += res.heat;
  if (energy_on) {    // a wall contact counts fully on its atom; a run's setup is no step
    if (update_history)
      for (int k = 0; k < viscontact::NDISS; k++) ediss[i][k] += res.dissipated[k];
    for (int k = 0; k < viscontact::NELASTIC; k++) eel[i][k] += res.elastic[k];
  }
  if (peratom_flag) {    // native's 8 columns; the last contact of the atom wins
    double *a = array_atom[i];
    a[0] = 1.0;
    for (int d = 0; d < 3; d++) {
      a[1 + d] = res.force[d];
      a[4 + d] = atom->x[i][d] - c.r * c.n[d];
    }
    a[7] = r;
  }
}

/* The wall's position (wlo, whi) and velocity (vplane) this step: planes and cylinder, from
   wiggle or shear. */
void FixWallViscontact::wall_motion(double &wlo, double &whi, double vplane[3]) const
{
  if (motion == WIGGLE) {
    const double arg = wfreq * static_cast<double>(update->ntimestep - time_origin) * update->dt;
    if (wallstyle == axis) {
      wlo = lo + amplitude - amplitude * std::cos(arg);
      whi = hi + amplitude - amplitude * std::cos(arg);
    }
    vplane[axis] = amplitude * wfreq * std::sin(arg);
  } else if (motion == SHEAR) {
    vplane[axis] = vshear;
  }
}

void FixWallViscontact::post_force(int /*vflag*/)
{
  // history advances only on regular steps (not in a run's setup), as LAMMPS granular
  const bool update_history = !update->setupflag;
  // (read once: stores to forces and histories could alias update's doubles)
  const double dt = update->dt, t_now = viscontact::time_now(update);
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;

  wallforce[0] = wallforce[1] = wallforce[2] = 0.0;
  wallforce_summed = false;
  if (neighbor->ago == 0) masses.refresh(atom);    // rigid-body masses of the local atoms
  if (heat_on && !tstr.empty()) twall = input->variable->compute_equal(tvar);

  double wlo = lo, whi = hi;
  double vplane[3] = {0.0, 0.0, 0.0};
  wall_motion(wlo, whi, vplane);
  // a region's motion: its transform and its velocity over the last step (once per step for
  // all fixes using the region)
  region_moving = region && region->dynamic_check();
  if (region_moving) {
    region->prematch();
    region->set_velocity();
  }
  if (region) frame.refresh(*region);
  if (meshwall) mesh_step();
  if (peratom_flag)
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < size_peratom_cols; k++) array_atom[i][k] = 0.0;
  if (energy_on)
    for (int i = 0; i < nlocal; i++)
      for (int k = 0; k < viscontact::NELASTIC; k++) eel[i][k] = 0.0;

  const int touch = model.history_slots().touch;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    // (a region with an open face matches every point: Region::match() would only transform
    // it, which for a moving region costs a sine and a cosine per atom and step)
    if (region && !region->openflag && !region_match(atom->x[i])) {
      // outside: no contact, and no stale history to come back with the atom
      if (nstored[i] != 0) {
        for (int k = 0; k < tmax; k++) goes_on[k] = 0;
        nstored[i] = end_contacts(i);
        store[i][0] = nstored[i];
      }
      continue;
    }
    if (!type_ok[atom->type[i]])    // a type without material (e.g. inserted since init)
      error->one(FLERR, std::string(PREFIX) + "no material for atom type " +
                            std::to_string(atom->type[i]) +
                            ": give particle E NU, or pair_coeff I I of pair viscontact");
    find_touches(i, wlo, whi, vplane);
    const viscontact::ContactModel &m = type_model[atom->type[i]];
    const int nold = nstored[i];
    const double rad = atom->radius[i];
    if (meshwall) mesh_inherit(i, nold);    // a relabelling only: setup too

    // each face's history by its wall index; a contact that goes on is evaluated where it is
    // stored (native's in-place update: no copy of the history per contact and step).  A run's
    // setup keeps and drops contacts as a step does and keeps what it writes (the Coulomb
    // caps), only the history does not advance: native fix wall/gran marks a contact touching
    // there (a jkr contact stretched in the first step keeps its attraction) and clears one no
    // longer touching
    if (nold == 0 && touches.empty()) continue;
    for (int k = 0; k < nold; k++) goes_on[k] = 0;
    int nfresh = 0, ngoing = 0;
    for (int t = 0; t < static_cast<int>(touches.size()); t++) {
      const Touch &c = touches[t];
      const int k = find_slot(i, nold, c.iwall);
      double *stored = k >= 0 ? slot(i, k) + 1 : nullptr;
      if (!touching(m, c, rad, stored && stored[touch] != 0.0))
        continue;
      if (stored) {
        goes_on[k] = 1;
        ngoing++;
        contact(i, stored, c, update_history, dt, t_now);
      } else {
        fresh[nfresh++] = t;    // new: after the ended contacts have left their slots
      }
    }
    // faces no longer touching: their contacts end (their elastic energy is released into
    // the dissipated columns); those that go on move up over them; a face found again later
    // starts from zero
    const int nkept =
        ngoing == nold ? nold
                       : end_contacts(i, wallstyle <= ZPLANE || (meshwall && !mesh_moving())
                                                ? vplane : nullptr);
    int n = nkept;
    for (int q = 0; q < nfresh; q++, n++) {
      const Touch &c = touches[fresh[q]];
      double *h = slot(i, n);
      h[0] = c.iwall;
      for (int v = 0; v < hsize; v++) h[1 + v] = 0.0;
      contact(i, h + 1, c, update_history, dt, t_now);
    }
    store[i][0] = nstored[i] = n;
  }
  if (meshwall) mesh_output();
  t0_restart = false;    // converted in the first force call after read_restart
}

namespace {
/* Region keeps the rotation's point and unit axis protected; a pointer to member formed in a
   derived class reads them from any Region (never instantiated). */
struct RegionAxis : Region {
  static const double *point_of(const Region &r) { return r.*(&RegionAxis::point); }
  static const double *unit_of(const Region &r) { return r.*(&RegionAxis::runit); }
};

/* x turned by the angle whose sine and cosine are s, c about the axis along the unit vector u
   through p (right-hand rule): x = p + C + A c + B s with D = x - p, C = (D.u) u, A = D - C,
   B = u x A.  Three scalars, not arrays: a point written as scalars and read back as a pair
   (the vectorizer's choice for arrays) waits for the stores to retire, on the critical path of
   every atom's wall search. */
VISCONTACT_ALWAYS_INLINE void rotate_about(double &x, double &y, double &z, const double p[3],
                                          const double u[3], double s, double c)
{
  const double d0 = x - p[0], d1 = y - p[1], d2 = z - p[2];
  const double along = d0 * u[0] + d1 * u[1] + d2 * u[2];
  const double c0 = along * u[0], c1 = along * u[1], c2 = along * u[2];
  const double a0 = d0 - c0, a1 = d1 - c1, a2 = d2 - c2;
  const double b0 = u[1] * a2 - u[2] * a1, b1 = u[2] * a0 - u[0] * a2, b2 = u[0] * a1 - u[1] * a0;
  x = p[0] + c0 + (a0 * c + b0 * s);
  y = p[1] + c1 + (a1 * c + b1 * s);
  z = p[2] + c2 + (a2 * c + b2 * s);
}
}    // namespace

void FixWallViscontact::RegionFrame::refresh(const Region &r)
{
  dynamic = r.dynamic != 0;
  move = r.moveflag != 0;
  rotate = r.rotateflag != 0;
  if (move) {
    d[0] = r.dx;
    d[1] = r.dy;
    d[2] = r.dz;
  }
  if (rotate) {
    for (int k = 0; k < 3; k++) {
      point[k] = RegionAxis::point_of(r)[k];
      unit[k] = RegionAxis::unit_of(r)[k];
    }
    sin_in = std::sin(-r.theta);
    cos_in = std::cos(-r.theta);
    sin_out = std::sin(r.theta);
    cos_out = std::cos(r.theta);
  }
  for (int k = 0; k < 3; k++) {
    v[k] = r.v[k];
    omega[k] = r.omega[k];
    rpoint[k] = r.rpoint[k];
  }
}

VISCONTACT_ALWAYS_INLINE void FixWallViscontact::RegionFrame::velocity(const double xc[3], double vw[3]) const
{
  for (int k = 0; k < 3; k++) vw[k] = move ? v[k] : 0.0;
  if (rotate) {    // omega x (xc - rpoint)
    vw[0] += omega[1] * (xc[2] - rpoint[2]) - omega[2] * (xc[1] - rpoint[1]);
    vw[1] += omega[2] * (xc[0] - rpoint[0]) - omega[0] * (xc[2] - rpoint[2]);
    vw[2] += omega[0] * (xc[1] - rpoint[1]) - omega[1] * (xc[0] - rpoint[0]);
  }
}

VISCONTACT_ALWAYS_INLINE void FixWallViscontact::RegionFrame::to_region(double &x, double &y,
                                                                      double &z) const
{
  if (move) {
    x -= d[0];
    y -= d[1];
    z -= d[2];
  }
  if (rotate) rotate_about(x, y, z, point, unit, sin_in, cos_in);
}

VISCONTACT_ALWAYS_INLINE void FixWallViscontact::RegionFrame::to_box(double &x, double &y,
                                                                   double &z) const
{
  if (rotate) rotate_about(x, y, z, point, unit, sin_out, cos_out);
  if (move) {
    x += d[0];
    y += d[1];
    z += d[2];
  }
}

/* Region::match(x) with this step's frame: inside (or outside, for `side out`) the region. */
bool FixWallViscontact::region_match(const double *x)
{
  if (!frame.dynamic) return region->match(x[0], x[1], x[2]) != 0;
  double xr = x[0], yr = x[1], zr = x[2];
  frame.to_region(xr, yr, zr);
  return !(region->inside(xr, yr, zr) ^ region->interior);
}

/* Region::surface(x, cutoff) with this step's frame: the region's faces within cutoff of x,
   in region->contact[], their vectors to x in the box's frame. */
int FixWallViscontact::region_surface(const double *x, double cutoff)
{
  if (!frame.dynamic) return region->surface(x[0], x[1], x[2], cutoff);
  double xr = x[0], yr = x[1], zr = x[2];
  frame.to_region(xr, yr, zr);
  double xnear[3] = {xr, yr, zr};    // (the region's functions take an array)
  // with an open face a point may touch faces from outside or inside, never both
  const int nc = !region->openflag
      ? (region->interior ? region->surface_interior(xnear, cutoff)
                          : region->surface_exterior(xnear, cutoff))
      : region->surface_exterior(xnear, cutoff) + region->surface_interior(xnear, cutoff);
  if (frame.rotate)
    for (int ic = 0; ic < nc; ic++) {
      auto &rc = region->contact[ic];
      double xs = xnear[0] - rc.delx, ys = xnear[1] - rc.dely, zs = xnear[2] - rc.delz;
      frame.to_box(xs, ys, zs);
      rc.delx = x[0] - xs;
      rc.dely = x[1] - ys;
      rc.delz = x[2] - zs;
    }
  return nc;
}

/* Does face c touch the sphere of radius rad (ContactModel::touching)?  R* (a division) only
   where it matters: a jkr contact that existed at the last step holds on to its pull-off
   distance. */
bool FixWallViscontact::touching(const viscontact::ContactModel &m, const Touch &c, double rad,
                                 bool touched) const
{
  if (touched && m.beyond_contact())
    return m.touching(c.r * c.r, rad, effective_radius(rad, c.rwall), true);
  return c.r * c.r < rad * rad;
}

/* The slot of atom i's stored contact with face iwall among its first nold, or -1. */
int FixWallViscontact::find_slot(int i, int nold, int iwall)
{
  for (int k = 0; k < nold; k++)
    if (static_cast<int>(slot(i, k)[0]) == iwall) return k;
  return -1;
}

/* The stored contacts of atom i whose goes_on flag is 0 end now (all of them for goes_on
   cleared): with the energy tally on, each releases its last elastic energy and the second
   half of its last forces' work into the dissipated columns (as pair viscontact does; on this
   step's velocities where the wall's is known, vplane of a plane wall).  Those that go on move
   to the front, in order; returns their number (the store's count is left to the caller). */
int FixWallViscontact::end_contacts(int i, const double *vplane)
{
  const int nold = nstored[i];
  viscontact::ContactGeometry now;
  if (energy_on && vplane) {
    for (int d = 0; d < 3; d++) {
      now.vr[d] = atom->v[i][d] - vplane[d];
      now.omega_i[d] = atom->omega[i][d];
      now.omega_j[d] = 0.0;
    }
    now.reff = atom->radius[i];    // a plane: R* = r
    now.dt = update->dt;
    now.wall = true;
  }
  int n = 0;
  for (int k = 0; k < nold; k++) {
    double *s = slot(i, k);
    if (!goes_on[k]) {
      if (energy_on && !update->setupflag)    // a run's setup is no step: it dissipates nothing
        type_model[atom->type[i]].release(s + 1, ediss[i], vplane ? &now : nullptr);
      continue;
    }
    if (n != k) std::memcpy(slot(i, n), s, sizeof(double) * slotsize);
    n++;
  }
  return n;
}

double FixWallViscontact::compute_vector(int k)
{
  if (k >= 3) return mesh_vector(k - 3);
  if (!wallforce_summed) {
    MPI_Allreduce(wallforce, wallforce_all, 3, MPI_DOUBLE, MPI_SUM, world);
    wallforce_summed = true;
  }
  return wallforce_all[k];
}

/* ---- global restart record: the format (as -3), the wiggle origin and a region's motion
   state.  Format 2 (viscontact before 2026-11-27) began with the wiggle origin (a step, >= 0)
   and its per-atom histories hold Jian's start time t0 where format 3 holds the relaxation g:
   the first force call converts them (t0_restart). ---- */

static constexpr bigint WALL_RESTART_FORMAT = 3;

void FixWallViscontact::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  int len = 0;
  if (region) region->length_restart_string(len);
  if (meshwall) len += mesh_restart_size();
  const int size = static_cast<int>(2 * sizeof(bigint)) + len;
  const bigint marker = -WALL_RESTART_FORMAT;
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(&marker, sizeof(bigint), 1, fp);
  fwrite(&time_origin, sizeof(bigint), 1, fp);
  if (region) region->write_restart(fp);
  if (meshwall) mesh_write_restart(fp);
}

void FixWallViscontact::restart(char *buf)
{
  bigint first;
  std::memcpy(&first, buf, sizeof(bigint));
  int n = static_cast<int>(sizeof(bigint));
  if (first >= 0) {    // format 2: the wiggle origin first
    time_origin = first;
    t0_restart = true;
  } else if (first == -WALL_RESTART_FORMAT) {
    std::memcpy(&time_origin, buf + n, sizeof(bigint));
    n += static_cast<int>(sizeof(bigint));
  } else {
    fail("this restart file holds wall format " + std::to_string(-first) + "; this viscontact "
         "reads formats 2 and " + std::to_string(WALL_RESTART_FORMAT) + ": define the fix "
         "again after read_restart (its contacts then start afresh)");
  }
  if (meshwall) mesh_restart(buf + n);
  if (region) {
    if (!region->restart(buf, n)) {
      if (comm->me == 0)
        error->warning(FLERR, std::string(PREFIX) + "region " + idregion +
                                  " differs from the restart file's: its motion restarts");
      region->reset_vel();
    }
  }
}

/* ---- per-atom history and energy: grow, copy, migrate, restart ----------------------------

   Per atom: the contacts' store (nvalues), the cumulative dissipated energy (NDISS; migrates
   and goes to restart files), the elastic energy (NELASTIC; recomputed at every force
   computation) and, with `contacts`, native's 8 columns. */

namespace {
constexpr int NDISS = viscontact::NDISS;
constexpr int NELASTIC = viscontact::NELASTIC;
}    // namespace

void FixWallViscontact::grow_arrays(int nmax)
{
  memory->grow(store, nmax, nvalues, "viscontact/wall:history");
  memory->grow(nstored, nmax, "viscontact/wall:contacts_stored");
  memory->grow(ediss, nmax, NDISS, "viscontact/wall:dissipated");
  memory->grow(eel, nmax, NELASTIC, "viscontact/wall:elastic");
  if (peratom_flag) memory->grow(array_atom, nmax, size_peratom_cols, "viscontact/wall:contacts");
}

void FixWallViscontact::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int m = 0; m < nvalues; m++) store[j][m] = store[i][m];
  nstored[j] = nstored[i];
  for (int m = 0; m < NDISS; m++) ediss[j][m] = ediss[i][m];
  for (int m = 0; m < NELASTIC; m++) eel[j][m] = eel[i][m];
  if (peratom_flag)
    for (int m = 0; m < size_peratom_cols; m++) array_atom[j][m] = array_atom[i][m];
}

void FixWallViscontact::set_arrays(int i)
{
  for (int m = 0; m < nvalues; m++) store[i][m] = 0.0;
  nstored[i] = 0;
  for (int m = 0; m < NDISS; m++) ediss[i][m] = 0.0;
  for (int m = 0; m < NELASTIC; m++) eel[i][m] = 0.0;
  if (peratom_flag)
    for (int m = 0; m < size_peratom_cols; m++) array_atom[i][m] = 0.0;
}

int FixWallViscontact::pack_exchange(int i, double *buf)
{
  int n = 0;
  for (int m = 0; m < nvalues; m++) buf[n++] = store[i][m];
  for (int m = 0; m < NDISS; m++) buf[n++] = ediss[i][m];
  if (peratom_flag)
    for (int m = 0; m < size_peratom_cols; m++) buf[n++] = array_atom[i][m];
  return n;
}

int FixWallViscontact::unpack_exchange(int nlocal, double *buf)
{
  int n = 0;
  for (int m = 0; m < nvalues; m++) store[nlocal][m] = buf[n++];
  nstored[nlocal] = static_cast<int>(store[nlocal][0]);
  for (int m = 0; m < NDISS; m++) ediss[nlocal][m] = buf[n++];
  for (int m = 0; m < NELASTIC; m++) eel[nlocal][m] = 0.0;
  if (peratom_flag)
    for (int m = 0; m < size_peratom_cols; m++) array_atom[nlocal][m] = buf[n++];
  return n;
}

int FixWallViscontact::pack_restart(int i, double *buf)
{
  // first value: how many values this fix wrote for the atom, itself included
  int n = 1;
  for (int m = 0; m < nvalues; m++) buf[n++] = store[i][m];
  for (int m = 0; m < NDISS; m++) buf[n++] = ediss[i][m];
  buf[0] = n;
  return n;
}

void FixWallViscontact::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;    // skip the values of the fixes before this one
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  if (static_cast<int>(extra[nlocal][m]) != size_restart(nlocal))
    error->one(FLERR, std::string(PREFIX) +
                          "restart file holds a different wall history size (was the wall style, "
                          "region or contact model changed between write_restart and "
                          "read_restart?)");
  m++;
  for (int k = 0; k < nvalues; k++) store[nlocal][k] = extra[nlocal][m++];
  nstored[nlocal] = static_cast<int>(store[nlocal][0]);
  for (int k = 0; k < NDISS; k++) ediss[nlocal][k] = extra[nlocal][m++];
}

int FixWallViscontact::size_restart(int /*nlocal*/)
{
  return 1 + nvalues + NDISS;
}

int FixWallViscontact::maxsize_restart()
{
  return 1 + nvalues + NDISS;
}

double FixWallViscontact::memory_usage()
{
  return static_cast<double>(atom->nmax) *
      ((nvalues + NDISS + NELASTIC + (peratom_flag ? size_peratom_cols : 0)) * sizeof(double) +
       sizeof(int));
}
