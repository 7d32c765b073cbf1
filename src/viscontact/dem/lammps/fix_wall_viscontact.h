/* fix viscontact/wall: walls acting on spheres with the viscontact contact model.

     fix ID GROUP viscontact/wall WALL wall_material (E NU | rigid) [normal hertz|dmt W|jkr W]
         damping ... tangential ... [rolling ...] [twisting ...] [heat area K]
         [temperature T|v_name] [wiggle DIM A PERIOD | shear DIM V] [particle E NU] [contacts]
       WALL = xplane LO HI | yplane LO HI | zplane LO HI   (LO, HI a coordinate or NULL)
            | zcylinder R                                  (axis z through the origin)
            | region REGION-ID                             (any LAMMPS region, may move/rotate)
            | mesh FILE [mesh keywords]                    (an STL triangle mesh, may move/rotate;
                                                            fix_wall_viscontact_mesh.h)

   Defaults: normal hertz; `end force` with hertz, `end overlap` with dmt/jkr; heat needs
   temperature (and per-atom temperature/heatflow), temperature needs heat.

   Geometry (one "contact" = one wall face touching the sphere; each has its own history):
   - planes: only the nearer of LO and HI acts (as LAMMPS fix wall/gran); n points from the
     wall into the sphere, delta = r - distance, the wall is flat (R* = r).
   - zcylinder: radial distance to the cylinder of radius R; the wall's curvature radius is
     -2R for a sphere inside and +2R outside (LAMMPS's convention), R* = r rw/(r + rw).
   - region: every face that Region::surface() finds within r of the sphere centre is one
     contact, keyed by the face's wall index (Region::Contact::iwall), with R* from the face's
     signed curvature radius (0 flat, < 0 concave).  More contacts than the region allows
     (Region::tmax) is an error.  Spheres outside the region are skipped and their wall history
     cleared.  The wall velocity at a contact is the region's: Region::prematch(),
     set_velocity() once per step, then Region::velocity_contact()'s formula per contact
     (translation over the last step / dt, rotation omega x (x_c - point), variable shapes);
     zero for a static region.  A moving region's transform (Region::match() and surface()
     take a sine and a cosine of its angle per point) is done here with the sine and cosine
     taken once per step (RegionFrame): the same arithmetic, the same doubles.
   - wiggle DIM A PERIOD: the wall oscillates along DIM; a plane normal to DIM sits at
     LO/HI + A (1 - cos(w t)), w = 2 pi/PERIOD, t = (step - step the fix was defined) dt; the
     wall velocity along DIM is A w sin(w t).  zcylinder: DIM z only.
   - shear DIM V: a plane moves at V along DIM (DIM in the plane); a zcylinder slides along z
     (DIM z) or turns about z (DIM x or y) with surface speed V: wall velocity
     V (y, -x)/sqrt(x^2 + y^2) at the sphere (LAMMPS documents this; its code accumulates the
     velocity over atoms, which we do not reproduce).  wiggle + shear, or either with region,
     is an error.

   Contact model: the one viscontact contact step (viscontact::ContactModel::evaluate,
   viscontact_model.h; the same keywords as pair viscontact, ContactKeywords) with the
   wall as body j: r_j = 0 (R* from the curvature above), m* = m_i (the body's mass in a rigid
   body), w_j = 0, v_j = the wall velocity, lever arm r_i, T_j = the wall temperature.  A jkr
   contact with a plane or the cylinder lives until pull-off (delta > -delta_c(R*)); with a
   region it ends at zero overlap (LAMMPS fix wall/gran/region searches within r only).  Materials: 1/E* = (1-nu_p^2)/E_p +
   (1-nu_w^2)/E_w, 1/G* = (2-nu_p)/G_p + (2-nu_w)/G_w; `rigid` drops the wall terms; the
   particle's E, nu from `particle E NU`, else from pair viscontact's `pair_coeff I I`.

   History per atom: up to tmax contacts (1 for planes and zcylinder), each [wall index, the
   contact model's history].  It migrates with the atom and is written to restart files; a
   region's motion state and the wiggle origin go to the global restart record.  A run's setup
   evaluates stored contacts in place (the Coulomb cap may rewrite them, as native) and new
   ones on a scratch copy; it neither adds nor ends contacts.

   Energy (viscontact::EnergySource, read by compute viscontact/energy once it asks): per atom,
   the cumulative energy its wall contacts dissipated, by mechanism (migrates, restart), and
   their elastic energy now; a wall contact counts fully on its atom.  A contact that ends
   releases its last elastic energy into the dissipated columns (ContactModel::release).

   Output: global vector (3), the total force of the wall on the group; with `contacts`, the
   per-atom array of LAMMPS fix wall/gran (8 columns: touching flag, force x y z of the last
   contact, contact point x y z, sphere radius).

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_FIX_WALL_VISCONTACT_H
#define VISCONTACT_FIX_WALL_VISCONTACT_H

#include "fix.h"
#include "update.h"
#include "viscontact_lammps.h"
#include "viscontact_model.h"

#include <cstdint>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixWallViscontact : public Fix, public viscontact::EnergySource {
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
  void write_restart(FILE *) override;
  void restart(char *) override;
  double memory_usage() override;

  // viscontact::EnergySource: per local atom, the cumulative energy its wall contacts
  // dissipated (by mechanism) and their elastic energy now, all counted on the atom
  void energy_request() override { energy_on = true; }
  const double *energy_dissipated_atom() const override { return ediss ? ediss[0] : nullptr; }
  const double *energy_elastic_atom() const override { return eel ? eel[0] : nullptr; }

 private:
  enum Style { XPLANE = 0, YPLANE = 1, ZPLANE = 2, ZCYLINDER = 3, REGION = 4, MESH = 5 };
  int wallstyle;
  bool has_lo, has_hi;     // plane walls present (NULL: absent)
  double lo, hi, cylradius;
  std::string idregion;
  class Region *region;
  int tmax;                // most contacts one sphere can have with this wall

  // wall motion (planes, zcylinder)
  enum Motion { STILL, WIGGLE, SHEAR };
  int motion;
  int axis;                // DIM of wiggle/shear: 0, 1, 2
  double amplitude, wfreq, vshear;
  bigint time_origin;      // the step the fix was defined (wiggle phase 0)

  viscontact::ContactModel model;       // as parsed (E*, G* filled per type in init)
  std::vector<viscontact::ContactModel> type_model;    // [ntypes+1]: with the type's E*, G*
  std::vector<char> type_ok;            // [ntypes+1]: the type has a material
  bool wall_rigid;
  double wall_E, wall_nu;
  bool has_twall;          // `temperature` given (required by heat)
  double twall;            // the wall temperature (constant)
  std::string tstr;        // or the name of an equal-style variable
  int tvar;
  bool has_particle;
  double particle_E, particle_nu;

  // k, c0, tau depend on (type, m, R*) only: a direct-mapped cache keeps the alpha form's
  // powers out of the step for the few distinct spheres of most packings
  struct Coeffs {
    int type = -1;
    double m = 0.0, r = 0.0;
    viscontact::ContactCoeffs cc{0.0, 0.0, 0.0};
  };
  static constexpr int CACHE_BITS = 8;
  std::vector<Coeffs> cache;
  const Coeffs *last_coeffs = nullptr;    // the entry of the last lookup
  /// k, c0, tau (and the relaxation's step factors) of a sphere of type, mass m and R* reff;
  /// most packings have one sphere size: the entry of the last lookup is tried first
  const viscontact::ContactCoeffs &coeffs(int type, double m, double reff)
  {
    const Coeffs *c = last_coeffs;
    if (c && c->type == type && c->m == m && c->r == reff && c->cc.step == update->dt) return c->cc;
    return coeffs_lookup(type, m, reff);
  }
  const viscontact::ContactCoeffs &coeffs_lookup(int type, double m, double reff);

  // per-atom storage: [0] number of stored contacts, then tmax slots of
  // [wall index, the contact model's history (hsize values)]
  int hsize, slotsize;
  int nvalues;
  double **store;
  double *slot(int i, int k) { return &store[i][1 + k * slotsize]; }
  int *nstored;                // per atom: its stored contacts (store[i][0], compact: the
                               // atoms away from the wall do not touch their store rows)
  bool region_moving = false;  // the region's dynamic_check() this step

  /// A moving region's placement this step (Region::dx dy dz, theta about the axis through
  /// its point): Region::match() and surface() take a sine and a cosine of theta for every
  /// point they transform; here they are taken once per step (refresh) and every point of
  /// the step reuses them.  The arithmetic is Region's rotation (Rodrigues' formula about the
  /// axis, around the unmoved point, then the displacement), in the same order: the same
  /// doubles as Region's own transforms.
  struct RegionFrame {
    bool dynamic = false, move = false, rotate = false;
    double d[3], point[3], unit[3];
    double sin_in, cos_in, sin_out, cos_out;    // of -theta (into the region), +theta
    double v[3], omega[3], rpoint[3];           // Region::set_velocity()'s, this step
    void refresh(const class Region &r);
    void to_region(double &x, double &y, double &z) const;    // undisplace, then unrotate
    void to_box(double &x, double &y, double &z) const;       // rotate, then displace
    // Region::velocity_contact(): the wall's velocity at the contact point xc
    void velocity(const double xc[3], double vw[3]) const;
  };
  RegionFrame frame;
  int region_surface(const double *x, double cutoff);
  bool region_match(const double *x);
  bool t0_restart = false;     // a format-2 restart: the stored Jian slots hold t0 (restart())
  std::vector<char> goes_on;   // per stored contact of one atom: touched again this step
  std::vector<int> fresh;      // this step's touches that are new contacts
  int find_slot(int i, int nold, int iwall);

  // energy (compute viscontact/energy): cumulative dissipation (migrates, restart) and the
  // elastic energy of the last force computation, NDISS and NELASTIC per atom
  bool energy_on;
  double **ediss, **eel;
  bool heat_on;

  viscontact::EffectiveMass masses;    // m* = the sphere's (or its rigid body's) mass

  double wallforce[3], wallforce_all[3];
  bool wallforce_summed;

  /// One wall face touching (or near) sphere i this step.
  struct Touch {
    int iwall;          // key of its history (plane: 0 lo, 1 hi; cylinder 0; region: face)
    double r;           // distance from the surface point to the centre (> 0)
    double n[3];        // unit normal from the wall into the sphere
    double rwall;       // signed curvature radius of the wall there (0: flat)
    double vwall[3];    // wall velocity at the contact
  };
  std::vector<Touch> touches;
  void find_touches(int i, double wlo, double whi, const double vplane[3]);
  void wall_motion(double &wlo, double &whi, double vplane[3]) const;
  bool touching(const viscontact::ContactModel &m, const Touch &c, double rad,
                bool touched) const;

  // the mesh style (fix_wall_viscontact_mesh.cpp)
  struct MeshWall *meshwall = nullptr;
  int mesh_parse(int narg, char **arg, int iarg);
  void mesh_free();
  void mesh_init();
  bool mesh_moving() const;
  void mesh_step();
  void mesh_touches(int i);
  void mesh_inherit(int i, int nold);
  void mesh_tally(int i, const Touch &c, const double *f);
  void mesh_output();
  double mesh_vector(int k);
  int mesh_restart_size() const;
  void mesh_write_restart(FILE *fp);
  void mesh_restart(const char *buf);

  [[noreturn]] void fail(const std::string &msg);
  int parse_wall(int narg, char **arg);
  void parse_keywords(const std::vector<std::string> &args);
  size_t parse_motion(const std::vector<std::string> &args, size_t i);
  double parse_coordinate(const std::string &key, const char *text, bool &present);
  int parse_dim(const std::string &key, const std::string &text);
  void contact(int i, double *hist, const Touch &c, bool update_history, double dt,
               double t_now);
  int end_contacts(int i, const double *vplane = nullptr);
  double effective_radius(double r, double rwall) const
  {
    return rwall == 0.0 ? r : r * rwall / (r + rwall);
  }
};

}    // namespace LAMMPS_NS

#endif
