/* compute viscontact/energy (see compute_viscontact_energy.h).
   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */

#include "compute_viscontact_energy.h"

#include "atom.h"
#include "error.h"
#include "fix.h"
#include "memory.h"
#include "modify.h"
#include "update.h"
#include "viscontact_model.h"

using namespace LAMMPS_NS;
namespace vc = viscontact;

static constexpr int NCOL = 2 + vc::NDISS + vc::NELASTIC;    // 12

ComputeViscontactEnergy::ComputeViscontactEnergy(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), energy(nullptr)
{
  if (narg != 3)
    error->all(FLERR, "compute viscontact/energy takes no arguments: compute ID GROUP "
                      "viscontact/energy");
  vector_flag = 1;
  size_vector = NCOL;
  extvector = 1;
  peratom_flag = 1;
  size_peratom_cols = NCOL;
  vector = new double[NCOL];
  for (int k = 0; k < NCOL; k++) vector[k] = 0.0;
}

ComputeViscontactEnergy::~ComputeViscontactEnergy()
{
  delete[] vector;
  memory->destroy(energy);
}

/* Every fix that implements viscontact::EnergySource: the pair's history fix and the wall
   fixes. */
void ComputeViscontactEnergy::find_sources()
{
  sources.clear();
  for (Fix *f : modify->get_fix_list()) {
    auto *src = dynamic_cast<vc::EnergySource *>(f);
    if (src) sources.push_back(src);
  }
}

void ComputeViscontactEnergy::init()
{
  find_sources();
  if (sources.empty())
    error->all(FLERR, "compute viscontact/energy needs pair viscontact (after its first run "
                      "setup) or a fix viscontact/wall");
  for (auto *src : sources) src->energy_request();
}

/* Row of atom i: [dissipated total, NDISS mechanisms, elastic total, NELASTIC parts]. */
void ComputeViscontactEnergy::fill_atom(int i, double *row) const
{
  for (int k = 0; k < NCOL; k++) row[k] = 0.0;
  for (auto *src : sources) {
    const double *d = src->energy_dissipated_atom();
    const double *e = src->energy_elastic_atom();
    for (int k = 0; d && k < vc::NDISS; k++) row[1 + k] += d[(size_t) i * vc::NDISS + k];
    for (int k = 0; e && k < vc::NELASTIC; k++)
      row[2 + vc::NDISS + k] += e[(size_t) i * vc::NELASTIC + k];
  }
  for (int k = 0; k < vc::NDISS; k++) row[0] += row[1 + k];
  for (int k = 0; k < vc::NELASTIC; k++) row[1 + vc::NDISS] += row[2 + vc::NDISS + k];
}

void ComputeViscontactEnergy::compute_vector()
{
  invoked_vector = update->ntimestep;
  find_sources();    // a wall fix may have been added or removed since init
  double local[NCOL] = {0.0}, row[NCOL];
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    fill_atom(i, row);
    for (int k = 0; k < NCOL; k++) local[k] += row[k];
  }
  MPI_Allreduce(local, vector, NCOL, MPI_DOUBLE, MPI_SUM, world);
}

void ComputeViscontactEnergy::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  find_sources();
  if (atom->nmax > nmax) {
    memory->destroy(energy);
    nmax = atom->nmax;
    memory->create(energy, nmax, NCOL, "viscontact/energy:energy");
    array_atom = energy;
  }
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++) {
    if (mask[i] & groupbit) fill_atom(i, energy[i]);
    else
      for (int k = 0; k < NCOL; k++) energy[i][k] = 0.0;
  }
}

double ComputeViscontactEnergy::memory_usage()
{
  return (double) nmax * NCOL * sizeof(double);
}
