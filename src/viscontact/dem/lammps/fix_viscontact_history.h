/* Internal fix VISCONTACT_HISTORY: per-contact history of `pair viscontact`.

   Created by the pair style in init_style (ID VISCONTACT_HISTORY_<n>, group all).  Between
   neighbour-list builds the history lives in per-neighbour arrays aligned with the pair's
   half list (flag + dnum doubles per i-j entry, seen from i; dnum and the layout come from the
   pair's contact models, viscontact_model.h).  Before atoms migrate
   (pre_exchange), at the end of every run (post_run) and before a restart file is written, each
   touching contact is copied to per-atom partner lists keyed by the partner's atom ID, on both
   atoms (the j copy with the tangential, rolling and twisting displacements negated; newton on: ghost copies go to
   their owners by a reverse communication).  The fix also keeps each atom's cumulative
   dissipated energy by mechanism (migrates, restart) and its current elastic energy, for
   compute viscontact/energy.  The partner lists travel with the atoms
   (pack_exchange) and into restart files (pack_restart); after each build (post_neighbor) the
   per-neighbour arrays are filled again from them by partner ID.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_FIX_HISTORY_H
#define VISCONTACT_FIX_HISTORY_H

#include "fix.h"
#include "viscontact_lammps.h"

#include <vector>

namespace LAMMPS_NS {

class PairViscontact;

class FixViscontactHistory : public Fix, public viscontact::EnergySource {
 public:
  FixViscontactHistory(class LAMMPS *, int, char **);
  ~FixViscontactHistory() override;
  int setmask() override;
  void init() override;
  void setup_post_neighbor() override;
  void pre_exchange() override;
  void post_neighbor() override;
  void setup(int) override;
  void post_run() override;
  void min_pre_exchange() override { pre_exchange(); }
  void min_post_neighbor() override { post_neighbor(); }
  void write_restart(FILE *) override;
  void restart(char *) override {}

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  int pack_reverse_comm_size(int, int) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;

  /// per-neighbour history of list entry (ilist index ii's atom i, neighbour jj):
  /// touch flag and HISTORY_SIZE values
  char *flags_of(int i) { return &pairflag[offset[i]]; }
  double *values_of(int i) { return &pairval[(size_t) offset[i] * dnum]; }
  bool ready() const { return list_valid; }

  /// Values per contact (the pair's history_size()).
  int history_size() const { return dnum; }
  /// Per-step energies from the pair (per atom, local + ghost rows, already reverse-summed):
  /// dissipated (NDISS columns) added to the cumulative arrays when advance, elastic (NELASTIC)
  /// stored as the atoms' current elastic energy.
  void add_energy(const double *diss, const double *elastic, bool advance);

  // viscontact::EnergySource
  void energy_request() override;
  const double *energy_dissipated_atom() const override { return ediss.data(); }
  const double *energy_elastic_atom() const override { return eel.data(); }

  PairViscontact *pair;
  int drop_history;    ///< negative control of the tests ($VISCONTACT_TEST_DROP_HISTORY=1)

 private:
  int dnum;                                  // values per contact
  int newton_pair;
  std::vector<std::vector<double>> store;    // per atom: [tag, dnum values] * npartner
  std::vector<long> offset;                  // per atom i of the list: first entry index
  std::vector<char> pairflag;
  std::vector<double> pairval;
  std::vector<double> ediss;    // per atom: cumulative dissipated energy, NDISS columns
  std::vector<double> eel;      // per atom: elastic energy now, NELASTIC columns
  bool list_valid;          // per-neighbour arrays match the current list and atom order
  bool partners_current;    // partner lists hold everything the per-neighbour arrays do
  int maxpartner;
  int nlocal_neigh, nall_neigh;    // atom counts when the list was built

  void store_partners();
  void add_partner(int i, double tag, const double *v, double sign);
  void update_maxexchange();
};

}    // namespace LAMMPS_NS

#endif
