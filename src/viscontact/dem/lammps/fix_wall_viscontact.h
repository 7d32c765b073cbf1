/* fix viscontact/wall: static walls acting on spheres with the viscontact contact laws.

     fix ID GROUP viscontact/wall WALLSTYLE ARGS wall_material (E NU | rigid)
         damping LAW [p P] FORM [end force|overlap] tangential TANG [particle E NU]
       WALLSTYLE ARGS = xplane LO HI | yplane LO HI | zplane LO HI   (LO, HI a coordinate or NULL)
                      | zcylinder R          (inner wall of the cylinder x^2 + y^2 = R^2)
       FORM, TANG as in pair viscontact (viscontact_keywords.h)

   Sphere-wall contact (SPEC sections 9, 10.8): R* = r, m* = m (the body's mass for a sphere in
   a rigid body), 1/E* = (1-nu_p^2)/E_p + (1-nu_w^2)/E_w,
   1/G* = (2-nu_p)/G_p + (2-nu_w)/G_w (rigid wall: its terms are 0).  The particle's E, nu come
   from `particle E NU`, else from pair viscontact's `pair_coeff I I`.  The force law, c0 and tau
   per contact, the clamp, the Jian clock and the Mindlin step are those of
   viscontact_contact.h, exactly as in the pair style.  The cylinder is treated like a plane
   tangent at the contact point (R* = r, as LAMMPS fix wall/gran does).  Walls are static; the
   friction torque acts with the arm r, as in fix wall/gran (for KK, LAMMPS's `viscoelastic`,
   the two fixes agree to rounding: tests/test_dem_wall.py).  Any units style: each value in
   the style's units (docs/pair_viscontact.md).

   History per atom and wall: touch flag, tangential displacement xi[3], contact start time;
   it migrates with the atom and is written to restart files.  A run's setup reads it and
   never writes it (as pair viscontact and pair granular).  Global vector (3): the total force
   of the wall(s) on the group [N].

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_FIX_WALL_VISCONTACT_H
#define VISCONTACT_FIX_WALL_VISCONTACT_H

#include "fix.h"
#include "viscontact_contact.h"
#include "viscontact_lammps.h"

#include <cstdint>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixWallViscontact : public Fix {
 public:
  FixWallViscontact(class LAMMPS *, int, char **);
  ~FixWallViscontact() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  double compute_vector(int) override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;

 private:
  enum Style { XPLANE = 0, YPLANE = 1, ZPLANE = 2, ZCYLINDER = 3 };
  int wallstyle;
  int nwall;               // walls of this fix: 2 for a plane pair (lo, hi), 1 for a cylinder
  bool has_lo, has_hi;     // plane walls present (NULL: absent)
  double lo, hi, cylradius;

  viscontact::LawParams law;            // as parsed (Estar, Gstar filled per type in init)
  std::vector<viscontact::LawParams> type_law;    // [ntypes+1]: law with the type's E*, G*
  bool wall_rigid;
  double wall_E, wall_nu;
  bool has_particle;
  double particle_E, particle_nu;

  // k, c0, tau depend on (type, m, r) only: a direct-mapped cache keeps the alpha form's
  // powers out of the step for the few distinct spheres of most packings
  struct Coeffs {
    int type = -1;
    double m = 0.0, r = 0.0;
    viscontact::ContactCoeffs cc{0.0, 0.0, 0.0};
  };
  static constexpr int CACHE_BITS = 8;
  std::vector<Coeffs> cache;
  const viscontact::ContactCoeffs &coeffs(int type, double m, double r);

  // per atom: nwall * HIST values; per wall: touch flag, xi[3], contact start time
  static constexpr int HIST = 1 + viscontact::HISTORY_SIZE;
  int nvalues;
  double **history;

  viscontact::EffectiveMass masses;    // m* = the sphere's (or its rigid body's) mass

  double wallforce[3], wallforce_all[3];
  bool wallforce_summed;

  [[noreturn]] void fail(const std::string &msg);
  double parse_coordinate(const std::string &key, const char *text, bool &present);
  void contact(int i, int w, double delta, const double n[3], double rwall, bool update_history,
               double t_now);
};

}    // namespace LAMMPS_NS

#endif
