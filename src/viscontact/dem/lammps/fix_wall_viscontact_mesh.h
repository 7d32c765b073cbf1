/* The triangle-mesh wall style of fix viscontact/wall (docs/fix_viscontact_mesh.md):

     fix ID GROUP viscontact/wall mesh FILE [scale S] [orient AX AY AZ DEG] [offset X Y Z]
         [move v_X v_Y v_Z] [rotate v_THETA PX PY PZ RX RY RZ] [max_contacts N] [crease DEG]
         [vtk N FILE]
         wall_material ... (every keyword of the other wall styles but wiggle and shear)

   FILE: an STL file, binary or ASCII, placed on load as x -> R(orient) (S x) + offset.
   move/rotate: the mesh's motion as a LAMMPS region's (region ... move/rotate): displacement
   and angle are equal-style variables of time, rotate first about P then displace; the wall
   velocity is their change over the last step / dt, v + omega x (x_c - (P + d)) at the
   contact point x_c.  max_contacts: contacts one sphere may have with the mesh (default 4;
   more is an error naming the atom).  crease DEG: concave creases flatter than DEG degrees
   (default 30) give one contact (viscontact_mesh.h).  vtk N FILE: every N steps the placed mesh with the
   force of the group on each triangle, as a legacy VTK file (a '*' in FILE becomes the step).

   Global vector (6): the force of the wall on the group (1-3, as the other styles) and the
   torque of the group's contact forces on the mesh about P + d (the origin without rotate).

   The geometry and the contact rule: viscontact_mesh.h.  History keys: the triangle that gave
   the contact; a contact whose triangle changes (a sphere rolling across an edge) keeps its
   history when the new triangle shares a vertex with the old one (mesh_inherit).

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_FIX_WALL_VISCONTACT_MESH_H
#define VISCONTACT_FIX_WALL_VISCONTACT_MESH_H

#include "lmptype.h"
#include "viscontact_mesh.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

struct MeshWall {
  viscontact::mesh::TriangleMesh mesh;
  std::string file;
  // motion, as a region's
  bool moveflag = false, rotateflag = false;
  std::string xstr[3], tstr;    // variable names ("" for NULL)
  int xvar[3] = {-1, -1, -1}, tvar = -1;
  viscontact::mesh::Vec point{0.0, 0.0, 0.0}, runit{0.0, 0.0, 1.0};
  double d[3] = {0.0, 0.0, 0.0}, theta = 0.0;    // now
  double prev[4] = {0.0, 0.0, 0.0, 0.0};          // d and theta of the last step
  bool have_prev = false;
  bigint step = -1;                               // the step of d, theta
  double v[3] = {0.0, 0.0, 0.0}, omega[3] = {0.0, 0.0, 0.0};
  std::array<viscontact::mesh::Vec, 3> rot{};     // R(theta)
  // output
  int vtk_every = 0;
  std::string vtk_file;
  bool tally = false;                             // per-triangle forces this step
  std::vector<double> tri_force;                  // [3 ntri], the group on each triangle
  double torque[3] = {0.0, 0.0, 0.0}, torque_all[3] = {0.0, 0.0, 0.0};
  std::vector<viscontact::mesh::Hit> hits;

  bool moving() const { return moveflag || rotateflag; }
};

}    // namespace LAMMPS_NS

#endif
