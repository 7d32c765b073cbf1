/* viscontact_lammps.h -- what `pair viscontact` and `fix viscontact/wall` both take from LAMMPS,
   in one place: the effective mass m* of a contact (frozen partners, rigid bodies) and the
   checks of fixes that the contact model cannot serve (heat conduction).

   m* (as LAMMPS `pair granular` and `fix wall/gran` take it, measured on LAMMPS 22Jul2025):
     - m_i is the atom's rmass, or the total mass of its body when it belongs to a body of the
       one rigid-body fix (`fix rigid`, `rigid/small`, ...; refreshed at every neighbour-list
       build, sent to ghost atoms by the pair);
     - pair: m* = m_i m_j / (m_i + m_j); if i is in the group of the one `fix freeze`, m* = m_j,
       if j is, m* = m_i (both frozen: m_i);
     - wall: m* = m_i (freeze plays no role).
   The same m* enters the force and the per-contact c0 and tau of the alpha form.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_LAMMPS_H
#define VISCONTACT_LAMMPS_H

#include "atom.h"
#include "error.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"
#include "neighbor.h"

#include <string>
#include <vector>

namespace viscontact {

/// Effective masses of contacts (see the file comment).  init() once per run (LAMMPS init),
/// refresh() after each neighbour-list build, then mass() / pair_meff() per contact.
class EffectiveMass {
 public:
  /// Find the freeze and rigid-body fixes; more than one of either is an error (native).
  /// who: the style name for the message ("pair viscontact", "fix viscontact/wall").
  void init(LAMMPS_NS::LAMMPS *lmp, const std::string &who)
  {
    auto freezes = lmp->modify->get_fix_by_style("^freeze");
    if (freezes.size() > 1)
      lmp->error->all(FLERR, who + ": only one fix freeze at a time is allowed (as pair granular)");
    freeze_bit = freezes.empty() ? 0 : freezes.front()->groupbit;
    rigid = nullptr;
    for (auto *f : lmp->modify->get_fix_list()) {
      if (!f->rigid_flag) continue;
      if (rigid)
        lmp->error->all(FLERR, who + ": only one rigid-body fix at a time is allowed (as pair "
                                     "granular), found " + rigid->id + " and " + f->id);
      rigid = f;
    }
    body_mass.clear();
  }

  /// Body masses of the local atoms (0: not in a body).  Call when the neighbour lists were just
  /// built (atoms may have moved between ranks); returns true when there is a rigid fix, i.e.
  /// when the caller must forward the values to its ghost atoms.
  bool refresh(LAMMPS_NS::Atom *atom)
  {
    if (!rigid) return false;
    if ((int) body_mass.size() < atom->nmax) body_mass.resize(atom->nmax);
    int dim = 0;
    const int *body = static_cast<const int *>(rigid->extract("body", dim));
    const double *mbody = static_cast<const double *>(rigid->extract("masstotal", dim));
    for (int i = 0; i < atom->nlocal; i++)
      body_mass[i] = (body && mbody && body[i] >= 0) ? mbody[body[i]] : 0.0;
    return true;
  }

  /// Make room for ghost values (forward communication writes them).
  void grow(int nmax)
  {
    if ((int) body_mass.size() < nmax) body_mass.resize(nmax);
  }

  /// m_i: the body's mass for an atom in a rigid body, else its own mass.
  double mass(int i, const double *rmass) const
  {
    return (rigid && (size_t) i < body_mass.size() && body_mass[i] > 0.0) ? body_mass[i]
                                                                           : rmass[i];
  }

  /// m* of the pair (i, j): the frozen partner counts as infinitely heavy.
  double pair_meff(int i, int j, const double *rmass, const int *mask) const
  {
    const double mi = mass(i, rmass), mj = mass(j, rmass);
    if (mask[j] & freeze_bit) return mi;
    if (mask[i] & freeze_bit) return mj;
    return mi * mj / (mi + mj);
  }

  int freeze_bit = 0;                    ///< group bit of the one fix freeze (0: none)
  LAMMPS_NS::Fix *rigid = nullptr;       ///< the one rigid-body fix, if any
  std::vector<double> body_mass;         ///< per atom (local and, for the pair, ghost)
};

/// What compute viscontact/energy sums: a pair's history fix or a wall fix that implements it
/// exposes, per local atom, its cumulative dissipated energy by mechanism (NDISS columns in the
/// order of viscontact_model.h: normal damping, tangential damping, sliding, rolling, twisting,
/// adhesion hysteresis) and its elastic energy now (NELASTIC columns: normal, tangential,
/// rolling, twisting).  A pair contact gives half to each partner, a wall contact all to its
/// atom.  Arrays are row-major, atom->nlocal rows, valid after the last force computation.
class EnergySource {
 public:
  /// Start tallying (called by the compute's init; the tally starts at the next run).
  virtual void energy_request() = 0;
  /// Cumulative dissipated energy, NDISS per local atom (nullptr: none yet).
  virtual const double *energy_dissipated_atom() const = 0;
  /// Elastic energy now, NELASTIC per local atom (nullptr: none yet).
  virtual const double *energy_elastic_atom() const = 0;

 protected:
  ~EnergySource() = default;    // not deleted through this interface
};

/// Stop with one error line when a fix needs the contact model to conduct heat (fix heat/flow):
/// the laws carry no heat model yet, and a silent zero conduction would be a wrong answer.
inline void refuse_heat(LAMMPS_NS::LAMMPS *lmp, const std::string &who)
{
  auto heat = lmp->modify->get_fix_by_style("^heat/flow");
  if (!heat.empty())
    lmp->error->all(FLERR, who + " does not conduct heat; fix " + std::string(heat.front()->id) +
                               " (heat/flow) needs a contact model that does (pair granular with "
                               "heat area): remove one of them");
}

}    // namespace viscontact

#endif
