/* compute ID GROUP viscontact/energy

   The energy bookkeeping of pair viscontact and every fix viscontact/wall, over the group's
   atoms: a global vector of 12 (extensive) and a per-atom array of the same 12 columns,

     1 dissipated total, 2-7 dissipated by normal damping, tangential damping, sliding friction,
     rolling resistance, twisting resistance, adhesion hysteresis (JKR snap-in);
     8 elastic total, 9-12 elastic normal, tangential spring, rolling spring, twisting spring.

   Dissipated energies are cumulative since the tally started (the first run after this
   compute was defined; they migrate with the atoms and go into restart files); a pair contact
   gives half to each partner, a wall contact all to its atom.  Elastic energies are those of
   the contacts at the last force computation.  With kinetic, rotational and potential energy
   the sum is conserved to first order in the time step.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_COMPUTE_ENERGY_H
#define VISCONTACT_COMPUTE_ENERGY_H

#include "compute.h"
#include "viscontact_lammps.h"

#include <vector>

namespace LAMMPS_NS {

class ComputeViscontactEnergy : public Compute {
 public:
  ComputeViscontactEnergy(class LAMMPS *, int, char **);
  ~ComputeViscontactEnergy() override;
  void init() override;
  void compute_vector() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  std::vector<viscontact::EnergySource *> sources;
  int nmax;
  double **energy;    // per-atom array
  void find_sources();
  void fill_atom(int i, double *row) const;
};

}    // namespace LAMMPS_NS

#endif
