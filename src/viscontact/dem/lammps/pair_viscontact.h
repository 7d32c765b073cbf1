/* pair_style viscontact: Hertz spring + the viscoelastic damping laws of viscontact
   (LH Ts KK Li Hunt Jian power), clamp or attraction, Mindlin friction with per-contact history.

     pair_style viscontact
     pair_coeff I J hertz/material E NU damping LAW [p P] FORM [end force|overlap] tangential TANG
       FORM = alpha A vref V [beta B]  |  c0 C [tau S]        (beta / tau: Jian only)
       TANG = none | mindlin MU

   The force law is viscontact_contact.h; SPEC sections 9-10 have the physics, the user's
   reference is docs/pair_viscontact.md.  Cutoff (SPEC 10.7, as pair granular): per type the
   largest radius of moving atoms (and of what fix pour / fix deposit will insert) and of frozen
   atoms; a sphere that outgrows it later stops the run with an error.  m*: viscontact_lammps.h.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_PAIR_VISCONTACT_H
#define VISCONTACT_PAIR_VISCONTACT_H

#include "pair.h"
#include "viscontact_contact.h"
#include "viscontact_lammps.h"

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
  void unpack_forward_comm(int, int, double *) override;

  /// Called by the history fix when it is deleted (unfix, plugin unload): the next run stops
  /// with an error instead of using it.
  void history_fix_deleted() { fix_history = nullptr; history_lost = true; }

  /// The material of type itype as given by `pair_coeff I I` (for fix viscontact/wall):
  /// false when no pair_coeff I I was given.
  bool type_material(int itype, double &E, double &nu) const;
  /// Parsed coefficients of a type pair (after init: mixed ones too).
  const viscontact::LawParams &law_params(int itype, int jtype) const { return params[itype][jtype]; }

 protected:
  viscontact::LawParams **params;    // [ntypes+1][ntypes+1]
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

  void allocate();
  void set_cutoff_radii();
  void check_radii() const;
  void parse_coeff(int narg, char **arg, viscontact::LawParams &lp, double &E, double &nu);
  [[noreturn]] void fail(const std::string &msg);
};

}    // namespace LAMMPS_NS

#endif
