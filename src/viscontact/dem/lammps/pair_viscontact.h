/* pair_style viscontact: a complete granular contact model (normal hertz/material, dmt, jkr;
   the viscoelastic damping laws of viscontact; tangential, rolling, twisting, heat sub-models
   as LAMMPS pair granular's) per type pair; the contact step is viscontact_model.h.

     pair_style viscontact [CUT]
     pair_coeff I J NORMAL damping LAW [p P] FORM [end force|overlap] tangential TMODEL
                [rolling sds KR GAMMAR MUR] [twisting marshall | twisting sds KT GAMMAT MUT]
                [heat area K] [cutoff C]
       NORMAL = hertz/material E NU | dmt E NU W | jkr E NU W
       FORM   = alpha A vref V [beta B]  |  c0 C [tau S]        (beta / tau: Jian only)
       TMODEL = none | linear_nohistory XGAMMA MU | linear_history KT XGAMMA MU
              | mindlin[_rescale][/force] KT|NULL XGAMMA MU | mindlin MU

   The contact model is viscontact_model.h (its sub-models' headers cite the papers), the user's
   reference is docs/pair_viscontact.md.  Cutoff (as native pair granular, measured): per type the
   largest radius of moving atoms (and of what fix pour / fix deposit will insert) and of frozen
   atoms; a sphere that outgrows it later stops the run with an error.  m*: viscontact_lammps.h.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_PAIR_VISCONTACT_H
#define VISCONTACT_PAIR_VISCONTACT_H

#include "pair.h"
#include "update.h"
#include "viscontact_contact.h"
#include "viscontact_lammps.h"
#include "viscontact_model.h"

#include <vector>

namespace LAMMPS_NS {

class PairViscontact : public Pair {
 public:
  PairViscontact(class LAMMPS *);
  ~PairViscontact() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  double single(int, int, int, int, double, double, double, double &) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  double memory_usage() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  /// Called by compute viscontact/energy at init: from now on each step's dissipated and elastic
  /// energies are tallied per atom (half to each partner) into the history fix.
  void request_energy() { energy_requested = true; }
  class FixViscontactHistory *history_fix() const { return fix_history; }
  void unpack_forward_comm(int, int, double *) override;

  /// Called by the history fix when it is deleted (unfix, plugin unload): the next run stops
  /// with an error instead of using it.
  void history_fix_deleted() { fix_history = nullptr; history_lost = true; }

  /// The material of type itype as given by `pair_coeff I I` (for fix viscontact/wall):
  /// false when no pair_coeff I I was given.
  bool type_material(int itype, double &E, double &nu) const;
  /// The contact model of a type pair (after init: mixed ones too).
  const viscontact::ContactModel &contact_model(int itype, int jtype) const { return models[itype][jtype]; }
  /// The type pair's model as given by pair_coeff I I (normal kind and W, for the wall fix).
  const viscontact::ContactModel &type_model(int itype) const { return models[itype][itype]; }
  /// History values per contact (the largest model's) and their orientation-flip signs.
  int history_size() const { return dnum; }
  const std::vector<double> &history_signs() const { return hsign; }

 protected:
  viscontact::ContactModel **models;    // [ntypes+1][ntypes+1]
  double **cut_user;                 // `cutoff C` per type pair (-1: none)
  double cut_global;                 // pair_style viscontact CUT (-1: none)
  int dnum;                          // history values per contact
  std::vector<double> hsign;         // their signs when i and j swap
  double **Ein, **nuin;              // E and nu as given for (i, j)
  std::vector<double> maxrad_dynamic;    // per type: largest radius of moving atoms (cutoff)
  std::vector<double> maxrad_frozen;     // per type: largest radius of frozen atoms
  viscontact::EffectiveMass masses;      // m* rules (freeze, rigid bodies)
  struct CoeffCache {
    int itype = -1, jtype = -1;
    double meff = 0.0, reff = 0.0;
    viscontact::ContactCoeffs cc{0.0, 0.0, 0.0};
  };
  static constexpr int COEFF_CACHE_BITS = 8;
  std::vector<CoeffCache> coeff_cache;    // per-contact k, c0, tau by (types, m*, R*)
  int need_history;
  bool history_lost;    // the history fix was deleted behind the pair's back
  bigint radii_checked_run[2];    // first and last step of the run whose radii were checked
  class FixViscontactHistory *fix_history;

  static constexpr int MAX_HISTORY = 40;    // the largest ContactModel::history_size() (38)
  struct EnergyTally {
    std::vector<double> diss, elastic;    // this step, per atom (local and ghost)
    void add_pair(int i, int j, int nlocal, int newton_pair, const viscontact::ContactResult &r);
    void add_release(int i, int j, int nlocal, int newton_pair, const viscontact::ContactModel &m,
                     const double *h, double factor,
                     const viscontact::ContactGeometry *now = nullptr);
  };
  EnergyTally tally_;
  bool energy_requested = false;
  EnergyTally *energy_begin();
  void energy_end(EnergyTally *t, bool advance);
  void refresh_atoms();
  static void apply(double **f, double **torque, double *heatflow, int i, int j, bool both_sides,
                    const viscontact::ContactResult &res);
  void pair_geometry(int i, int j, const double dx[3], double rsq, double meff, double dt,
                     double t_now, viscontact::ContactGeometry &g) const;
  /// k, c0, tau (and the relaxation's step factors) of a contact; most packings have one or
  /// two kinds of contact: the entry of the last lookup is tried first
  const viscontact::ContactCoeffs &coeffs_of(int i, int j, int itype, int jtype, double meff,
                                             double reff, double dt)
  {
    const CoeffCache *e = last_coeffs;
    if (e && e->itype == itype && e->jtype == jtype && e->meff == meff && e->reff == reff &&
        e->cc.step == dt)
      return e->cc;
    return coeffs_lookup(i, j, itype, jtype, meff, reff);
  }
  const viscontact::ContactCoeffs &coeffs_lookup(int i, int j, int itype, int jtype, double meff,
                                                 double reff);
  const CoeffCache *last_coeffs = nullptr;    // the entry of the last lookup

  void allocate();
  void set_cutoff_radii();
  void check_radii() const;
  void parse_coeff(int narg, char **arg, viscontact::ContactModel &m, double &E, double &nu,
                   double &cut);
  bool heat_on;    // the type pairs conduct heat (heat area)
  viscontact::HistoryLayout layout;    // the largest history block of each kind over the type pairs
  int restart_format = 3;               // of the restart file being read
  /// a format-2 restart was read: its stored contacts hold Jian's start time t0, not the
  /// relaxation g; the first force call converts them (ContactModel::relaxation_from_start_time)
  bool t0_restart = false;
  std::vector<viscontact::Record> read_pair_record(FILE *fp, double head[3]);
  bool energy_on = false;    // a compute viscontact/energy existed at init: energies are tallied
  [[noreturn]] void fail(const std::string &msg);
};

}    // namespace LAMMPS_NS

#endif
