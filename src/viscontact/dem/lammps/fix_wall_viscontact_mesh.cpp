/* The triangle-mesh wall style of fix viscontact/wall: see fix_wall_viscontact_mesh.h for the
   syntax, viscontact_mesh.h for the geometry and the contact rule.  Every other part of the
   wall (the contact model, its history slots, energy, restart) is fix viscontact/wall's own.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#include "fix_wall_viscontact.h"
#include "fix_wall_viscontact_mesh.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "input.h"
#include "update.h"
#include "variable.h"
#include "viscontact_keywords.h"

#include <cmath>
#include <cstdio>
#include <cstring>

using namespace LAMMPS_NS;
namespace vm = viscontact::mesh;

namespace {
const char *const PREFIX = "fix viscontact/wall mesh: ";
const viscontact::Domain ANY_NUMBER{-1e300, 1e300, false};
constexpr int DEFAULT_MAX_CONTACTS = 4;
}    // namespace

/* Parses `mesh FILE [scale S] [orient AX AY AZ DEG] [offset X Y Z] [move ...] [rotate ...]
   [max_contacts N] [crease DEG] [vtk N FILE]` from arg[iarg] (FILE), loads and checks the mesh; returns the
   index of the first argument after the mesh's keywords. */
int FixWallViscontact::mesh_parse(int narg, char **arg, int iarg)
{
  if (iarg >= narg) fail("mesh needs the name of an STL file");
  meshwall = new MeshWall;
  MeshWall &w = *meshwall;
  w.file = arg[iarg++];
  vm::Placement place;
  tmax = DEFAULT_MAX_CONTACTS;
  auto number = [&](const std::string &key, int k, const viscontact::Domain &dom) {
    double v = 0.0;
    const std::string err = viscontact::parse_number(key, arg[k], dom, v);
    if (!err.empty()) fail(err);
    return v;
  };
  auto need = [&](const std::string &key, int n, const std::string &what) {
    if (iarg + n >= narg) fail("mesh " + key + " needs " + what);
  };
  auto variable = [&](const std::string &key, const char *text, bool null_ok) -> std::string {
    if (null_ok && std::strcmp(text, "NULL") == 0) return "";
    if (std::strncmp(text, "v_", 2) != 0 || text[2] == '\0')
      fail("mesh " + key + " takes equal-style variables as v_NAME" +
           (null_ok ? " or NULL" : "") + ", got " + viscontact::quoted(text));
    return text + 2;
  };
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (key == "scale") {
      need(key, 1, "S (> 0)");
      place.scale = number("mesh scale", iarg + 1, viscontact::POSITIVE_DOMAIN);
      iarg += 2;
    } else if (key == "orient") {
      need(key, 4, "AX AY AZ DEG (an axis and an angle in degrees)");
      for (int d = 0; d < 3; d++) place.axis[d] = number("mesh orient axis", iarg + 1 + d, ANY_NUMBER);
      place.angle = number("mesh orient DEG", iarg + 4, ANY_NUMBER);
      if (vm::norm(place.axis) == 0.0) fail("mesh orient: the axis cannot be zero");
      iarg += 5;
    } else if (key == "offset") {
      need(key, 3, "X Y Z");
      for (int d = 0; d < 3; d++) place.offset[d] = number("mesh offset", iarg + 1 + d, ANY_NUMBER);
      iarg += 4;
    } else if (key == "move") {
      need(key, 3, "v_X v_Y v_Z (equal-style variables of the displacement, or NULL)");
      for (int d = 0; d < 3; d++) w.xstr[d] = variable("move", arg[iarg + 1 + d], true);
      w.moveflag = true;
      iarg += 4;
    } else if (key == "rotate") {
      need(key, 7, "v_THETA PX PY PZ RX RY RZ (the angle in radians, a point, an axis)");
      w.tstr = variable("rotate", arg[iarg + 1], false);
      vm::Vec axis;
      for (int d = 0; d < 3; d++) {
        w.point[d] = number("mesh rotate P", iarg + 2 + d, ANY_NUMBER);
        axis[d] = number("mesh rotate R", iarg + 5 + d, ANY_NUMBER);
      }
      const double len = vm::norm(axis);
      if (len == 0.0) fail("mesh rotate: the axis R cannot be zero");
      for (int d = 0; d < 3; d++) w.runit[d] = axis[d] / len;
      w.rotateflag = true;
      iarg += 8;
    } else if (key == "max_contacts") {
      need(key, 1, "N (1 to 64)");
      const double n = number("mesh max_contacts", iarg + 1, viscontact::Domain{1.0, 64.0, false});
      if (n != std::floor(n)) fail("mesh max_contacts must be a whole number from 1 to 64");
      tmax = static_cast<int>(n);
      iarg += 2;
    } else if (key == "crease") {
      need(key, 1, "DEG (0 to 90 degrees)");
      w.mesh.set_crease(number("mesh crease", iarg + 1, viscontact::Domain{0.0, 90.0, false}));
      iarg += 2;
    } else if (key == "vtk") {
      need(key, 2, "N FILE (every N steps, N >= 1)");
      const double n = number("mesh vtk N", iarg + 1, viscontact::Domain{1.0, 1e9, false});
      if (n != std::floor(n)) fail("mesh vtk N must be a whole number of steps");
      w.vtk_every = static_cast<int>(n);
      w.vtk_file = arg[iarg + 2];
      iarg += 3;
    } else {
      break;
    }
  }
  const std::string err = w.mesh.load(w.file, place);
  if (!err.empty()) fail(err);
  w.rot = vm::rotation(w.runit, 0.0);
  if (w.vtk_every) w.tri_force.assign(3 * static_cast<size_t>(w.mesh.ntri()), 0.0);
  w.hits.reserve(tmax);
  size_vector = 6;
  return iarg;
}

void FixWallViscontact::mesh_free()
{
  delete meshwall;
  meshwall = nullptr;
}

bool FixWallViscontact::mesh_moving() const
{
  return meshwall && meshwall->moving();
}

void FixWallViscontact::mesh_init()
{
  MeshWall &w = *meshwall;
  auto find = [&](const std::string &name) {
    const int k = input->variable->find(name.c_str());
    if (k < 0) fail("mesh motion variable " + viscontact::quoted(name) + " does not exist");
    if (!input->variable->equalstyle(k))
      fail("mesh motion variable " + viscontact::quoted(name) + " must be equal-style");
    return k;
  };
  for (int d = 0; d < 3; d++) w.xvar[d] = w.xstr[d].empty() ? -1 : find(w.xstr[d]);
  w.tvar = w.rotateflag ? find(w.tstr) : -1;
}

/* The mesh's displacement and angle now, and its velocity over the last step (as a LAMMPS
   region's: zero at step 0 and on the first step the fix sees); once per step. */
void FixWallViscontact::mesh_step()
{
  MeshWall &w = *meshwall;
  w.torque[0] = w.torque[1] = w.torque[2] = 0.0;
  w.tally = w.vtk_every > 0 && !update->setupflag && update->ntimestep % w.vtk_every == 0;
  if (w.tally) std::fill(w.tri_force.begin(), w.tri_force.end(), 0.0);
  if (!w.moving() || w.step == update->ntimestep) return;
  w.step = update->ntimestep;
  for (int d = 0; d < 3; d++) w.d[d] = w.xvar[d] >= 0 ? input->variable->compute_equal(w.xvar[d]) : 0.0;
  if (w.rotateflag) {
    w.theta = input->variable->compute_equal(w.tvar);
    w.rot = vm::rotation(w.runit, w.theta);
  }
  const double now[4] = {w.d[0], w.d[1], w.d[2], w.theta};
  const bool first = !w.have_prev || update->ntimestep == 0;
  for (int d = 0; d < 3; d++) w.v[d] = first ? 0.0 : (now[d] - w.prev[d]) / update->dt;
  const double angvel = first ? 0.0 : (now[3] - w.prev[3]) / update->dt;
  for (int d = 0; d < 3; d++) w.omega[d] = angvel * w.runit[d];
  std::memcpy(w.prev, now, sizeof now);
  w.have_prev = true;
}

/* The contacts of sphere i with the mesh (viscontact_mesh.h), as Touch entries in the world
   frame: the sphere moved into the mesh's frame, the normal moved back. */
void FixWallViscontact::mesh_touches(int i)
{
  MeshWall &w = *meshwall;
  const double *x = atom->x[i];
  const double rad = atom->radius[i];
  const viscontact::ContactModel &m = type_model[atom->type[i]];
  vm::Vec xb{x[0], x[1], x[2]};
  if (w.moving()) {
    const vm::Vec rel{x[0] - w.d[0] - w.point[0], x[1] - w.d[1] - w.point[1],
                      x[2] - w.d[2] - w.point[2]};
    for (int a = 0; a < 3; a++)    // R^T rel + P
      xb[a] = w.rot[0][a] * rel[0] + w.rot[1][a] * rel[1] + w.rot[2][a] * rel[2] + w.point[a];
  }
  w.mesh.contacts(xb, rad + m.pulloff_distance(rad), w.hits);
  if (static_cast<int>(w.hits.size()) > tmax)
    error->one(FLERR, std::string(PREFIX) + "atom " + std::to_string(atom->tag[i]) + " touches " +
                          std::to_string(w.hits.size()) + " separate places of mesh " + w.file +
                          ", more than max_contacts " + std::to_string(tmax) +
                          ": raise max_contacts");
  Touch c;
  c.rwall = 0.0;    // flat faces, R* = r
  for (const vm::Hit &h : w.hits) {
    if (h.dist == 0.0) continue;    // the centre on the surface: no normal
    c.iwall = h.tri;
    c.r = h.dist;
    for (int d = 0; d < 3; d++)
      c.n[d] = w.moving() ? vm::dot(w.rot[d], h.n) : h.n[d];
    for (int d = 0; d < 3; d++) c.vwall[d] = w.v[d];
    if (w.rotateflag) {
      double arm[3];
      for (int d = 0; d < 3; d++) arm[d] = x[d] - c.r * c.n[d] - (w.point[d] + w.d[d]);
      c.vwall[0] += w.omega[1] * arm[2] - w.omega[2] * arm[1];
      c.vwall[1] += w.omega[2] * arm[0] - w.omega[0] * arm[2];
      c.vwall[2] += w.omega[0] * arm[1] - w.omega[1] * arm[0];
    }
    touches.push_back(c);
  }
}

/* Before atom i's contacts are matched with its stored ones by key: a contact whose triangle
   has no stored slot takes over the slot of a triangle sharing a vertex with it (a sphere that
   rolled or slid onto the neighbour), which is relabelled with the new triangle. */
void FixWallViscontact::mesh_inherit(int i, int nold)
{
  const MeshWall &w = *meshwall;
  unsigned long long cl = 0, ma = 0;    // claimed slots, matched touches (tmax <= 64)
  const int nt = static_cast<int>(touches.size());
  for (int j = 0; j < nt; j++)
    for (int k = 0; k < nold; k++)
      if (!(cl >> k & 1ULL) && static_cast<int>(slot(i, k)[0]) == touches[j].iwall) {
        cl |= 1ULL << k;
        ma |= 1ULL << j;
        break;
      }
  for (int j = 0; j < nt; j++) {
    if (ma >> j & 1ULL) continue;
    for (int k = 0; k < nold; k++)
      if (!(cl >> k & 1ULL) && w.mesh.adjacent(static_cast<int>(slot(i, k)[0]), touches[j].iwall)) {
        slot(i, k)[0] = touches[j].iwall;
        cl |= 1ULL << k;
        break;
      }
  }
}

/* One contact's force f (the wall on atom i) at the touch c: the torque on the mesh and, on an
   output step, the force on the triangle. */
void FixWallViscontact::mesh_tally(int i, const Touch &c, const double *f)
{
  MeshWall &w = *meshwall;
  double arm[3];
  for (int d = 0; d < 3; d++)
    arm[d] = atom->x[i][d] - c.r * c.n[d] - (w.rotateflag ? w.point[d] + w.d[d] : 0.0);
  // the group on the mesh: -f at the contact point
  w.torque[0] -= arm[1] * f[2] - arm[2] * f[1];
  w.torque[1] -= arm[2] * f[0] - arm[0] * f[2];
  w.torque[2] -= arm[0] * f[1] - arm[1] * f[0];
  if (w.tally)
    for (int d = 0; d < 3; d++) w.tri_force[3 * static_cast<size_t>(c.iwall) + d] -= f[d];
}

double FixWallViscontact::mesh_vector(int k)
{
  MeshWall &w = *meshwall;
  MPI_Allreduce(w.torque, w.torque_all, 3, MPI_DOUBLE, MPI_SUM, world);
  return w.torque_all[k];
}

/* On an output step: the placed mesh and the force of the group on each triangle, as legacy
   VTK polydata (rank 0 writes). */
void FixWallViscontact::mesh_output()
{
  MeshWall &w = *meshwall;
  if (!w.tally) return;
  const int nt = w.mesh.ntri();
  std::vector<double> all(w.tri_force.size(), 0.0);
  MPI_Reduce(w.tri_force.data(), all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM,
             0, world);
  if (comm->me != 0) return;
  std::string name = w.vtk_file;
  const size_t star = name.find('*');
  if (star != std::string::npos) name.replace(star, 1, std::to_string(update->ntimestep));
  FILE *fp = std::fopen(name.c_str(), "w");
  if (!fp) error->one(FLERR, std::string(PREFIX) + "cannot write the vtk file " + name);
  std::fprintf(fp, "# vtk DataFile Version 3.0\nviscontact mesh %s step " BIGINT_FORMAT
               "\nASCII\nDATASET POLYDATA\nPOINTS %d double\n",
               w.file.c_str(), update->ntimestep, w.mesh.nvert());
  for (int v = 0; v < w.mesh.nvert(); v++) {
    vm::Vec p = w.mesh.vertex(v);
    if (w.moving()) {    // rotate about P, then displace
      const vm::Vec rel = vm::sub(p, w.point);
      for (int d = 0; d < 3; d++) p[d] = vm::dot(w.rot[d], rel) + w.point[d] + w.d[d];
    }
    std::fprintf(fp, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
  }
  std::fprintf(fp, "POLYGONS %d %d\n", nt, 4 * nt);
  for (int t = 0; t < nt; t++) {
    const auto &c = w.mesh.corners(t);
    std::fprintf(fp, "3 %d %d %d\n", c[0], c[1], c[2]);
  }
  std::fprintf(fp, "CELL_DATA %d\nVECTORS force double\n", nt);
  for (int t = 0; t < nt; t++)
    std::fprintf(fp, "%.17g %.17g %.17g\n", all[3 * t], all[3 * t + 1], all[3 * t + 2]);
  std::fclose(fp);
}

/* ---- global restart record: the mesh's motion state at the last step ---------------------
   (displacement and angle, the velocity over that step, the step), so that a run continued
   from a restart file starts from the same wall position and velocity. */

namespace {
constexpr int NRESTART = 10;    // d[3], theta, v[3], omega[3]
}

int FixWallViscontact::mesh_restart_size() const
{
  return NRESTART * static_cast<int>(sizeof(double)) + static_cast<int>(sizeof(bigint));
}

void FixWallViscontact::mesh_write_restart(FILE *fp)
{
  const MeshWall &w = *meshwall;
  const double state[NRESTART] = {w.prev[0], w.prev[1], w.prev[2], w.prev[3], w.v[0], w.v[1],
                                  w.v[2], w.omega[0], w.omega[1], w.omega[2]};
  const bigint step = w.have_prev ? w.step : -1;
  fwrite(state, sizeof(double), NRESTART, fp);
  fwrite(&step, sizeof(bigint), 1, fp);
}

void FixWallViscontact::mesh_restart(const char *buf)
{
  MeshWall &w = *meshwall;
  double state[NRESTART];
  bigint step;
  std::memcpy(state, buf, sizeof state);
  std::memcpy(&step, buf + sizeof state, sizeof(bigint));
  if (step < 0 || !w.moving()) return;
  for (int d = 0; d < 3; d++) {
    w.prev[d] = w.d[d] = state[d];
    w.v[d] = state[4 + d];
    w.omega[d] = state[7 + d];
  }
  w.prev[3] = w.theta = state[3];
  w.rot = vm::rotation(w.runit, w.theta);
  w.step = step;
  w.have_prev = true;
}
