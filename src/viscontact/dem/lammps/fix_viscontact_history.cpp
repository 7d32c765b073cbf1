/* Internal fix VISCONTACT_HISTORY (see fix_viscontact_history.h).
   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */

#include "fix_viscontact_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "neigh_list.h"
#include "pair_viscontact.h"
#include "utils.h"
#include "viscontact_model.h"

#include <cstdlib>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

FixViscontactHistory::FixViscontactHistory(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), pair(nullptr), drop_history(0), dnum(0),
    list_valid(false), partners_current(true), maxpartner(0), nlocal_neigh(0), nall_neigh(0)
{
  if (narg != 4) error->all(FLERR, "fix VISCONTACT_HISTORY is internal to pair viscontact");
  dnum = utils::inumeric(FLERR, arg[3], false, lmp);
  if (dnum < 3 || dnum > 64) error->all(FLERR, "fix VISCONTACT_HISTORY: bad history size");
  restart_peratom = 1;
  restart_global = 1;
  create_attribute = 1;
  maxexchange_dynamic = 1;
  maxexchange = 1;
  newton_pair = force->newton_pair;
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) store[i].clear();
}

FixViscontactHistory::~FixViscontactHistory()
{
  // deleted by unfix or plugin unload while the pair still exists: tell it (its next run stops
  // with an error instead of using a dangling pointer)
  if (pair) pair->history_fix_deleted();
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
}

int FixViscontactHistory::setmask()
{
  return PRE_EXCHANGE | POST_NEIGHBOR | POST_RUN | MIN_PRE_EXCHANGE | MIN_POST_NEIGHBOR;
}

void FixViscontactHistory::init()
{
  if (!pair)
    error->all(FLERR, "fix VISCONTACT_HISTORY is internal to pair viscontact; do not define it");
  if (atom->tag_enable == 0) error->all(FLERR, "pair viscontact requires atom IDs");
  // negative control for the tests only (not part of the input syntax): every contact forgets
  // its history at each neighbour-list build
  const char *drop = std::getenv("VISCONTACT_TEST_DROP_HISTORY");
  drop_history = (drop && std::strcmp(drop, "1") == 0) ? 1 : 0;
  if (force->newton_pair != newton_pair)
    error->all(FLERR, "pair viscontact: the newton pair setting changed after the first run");
  // atoms that another fix moves in its pre_exchange must carry current partner lists
  for (auto &ifix : modify->get_fix_list()) {
    if (ifix == this) break;
    if (ifix->pre_exchange_migrate)
      error->all(FLERR, "pair viscontact: its history fix must come before fix {} ({}), which "
                 "migrates atoms; define that fix after the first run", ifix->id, ifix->style);
  }
}

/* Append one partner (tag, values) to atom i's list; flip: seen from the other atom, i.e. the
   displacements negated (the pair's history_signs). */
void FixViscontactHistory::add_partner(int i, double tag, const double *v, double flip)
{
  auto &s = store[i];
  s.push_back(tag);
  const std::vector<double> &sign = pair->history_signs();
  for (int k = 0; k < dnum; k++) s.push_back(flip < 0.0 ? sign[k] * v[k] : v[k]);
}

void FixViscontactHistory::energy_request()
{
  if (pair) pair->request_energy();
}

void FixViscontactHistory::add_energy(const double *diss, const double *elastic, bool advance)
{
  const int nlocal = atom->nlocal;
  if (advance)
    for (size_t k = 0; k < (size_t) nlocal * viscontact::NDISS; k++) ediss[k] += diss[k];
  std::memcpy(eel.data(), elastic, sizeof(double) * (size_t) nlocal * viscontact::NELASTIC);
}

void FixViscontactHistory::update_maxexchange()
{
  maxpartner = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    const int np = (int) (store[i].size() / (dnum + 1));
    if (np > maxpartner) maxpartner = np;
  }
  maxexchange = 1 + (dnum + 1) * maxpartner + viscontact::NDISS;
}

/* Per-neighbour arrays -> per-atom partner lists (both atoms of every touching contact).
   Needs the per-neighbour arrays to match the current atom order (list_valid). */
void FixViscontactHistory::store_partners()
{
  if (!list_valid || !pair) return;
  NeighList *list = pair->list;
  // atom counts of the list (a fix before this one may have added atoms in its pre_exchange)
  const int nlocal = nlocal_neigh;
  const int nclear = newton_pair ? nall_neigh : nlocal;
  for (int i = 0; i < nclear; i++) store[i].clear();
  tagint *tag = atom->tag;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    const int jnum = list->numneigh[i];
    const char *fl = flags_of(i);
    const double *val = values_of(i);
    for (int jj = 0; jj < jnum; jj++) {
      if (!fl[jj]) continue;
      const int j = jlist[jj] & NEIGHMASK;
      add_partner(i, (double) tag[j], &val[(size_t) dnum * jj], 1.0);
      if (newton_pair || j < nlocal) add_partner(j, (double) tag[i], &val[(size_t) dnum * jj], -1.0);
    }
  }
  // ghost copies go to their owners (newton off: the owner's own list has the pair)
  if (newton_pair) comm->reverse_comm_variable(this);
  for (int i = nlocal; i < MAX(nclear, atom->nlocal); i++) store[i].clear();
  update_maxexchange();
  partners_current = true;
}

/* During a run, before atoms migrate: afterwards the per-neighbour arrays are stale until the
   next build refills them (post_neighbor). */
void FixViscontactHistory::pre_exchange()
{
  store_partners();
  list_valid = false;
}

/* End of every run: partner lists current (for write_restart, or commands that add or delete
   atoms); the per-neighbour arrays stay in use for a following `run ... pre no`. */
void FixViscontactHistory::post_run()
{
  store_partners();
}

/* Every run's start: the run will change the per-neighbour history. */
void FixViscontactHistory::setup(int /*vflag*/)
{
  partners_current = false;
}

/* Global restart hook, called when a restart file is written: during a run the partner lists
   are brought up to date; after a run they already are (and the write_restart command has
   moved atoms since, so the per-neighbour arrays must not be read). */
void FixViscontactHistory::write_restart(FILE *fp)
{
  if (!partners_current) store_partners();
  if (comm->me == 0) {
    int size = 0;
    fwrite(&size, sizeof(int), 1, fp);
  }
}

void FixViscontactHistory::setup_post_neighbor()
{
  post_neighbor();
}

/* Per-atom partner lists -> per-neighbour arrays of the list just built. */
void FixViscontactHistory::post_neighbor()
{
  if (!pair) return;
  NeighList *list = pair->list;
  const int nall = atom->nlocal + atom->nghost;
  nlocal_neigh = atom->nlocal;
  nall_neigh = nall;
  if ((int) offset.size() < nall) offset.resize(nall);
  long total = 0;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    offset[i] = total;
    total += list->numneigh[i];
  }
  pairflag.assign(total, 0);
  pairval.assign((size_t) total * dnum, 0.0);
  tagint *tag = atom->tag;
  if (!drop_history) {
    for (int ii = 0; ii < list->inum; ii++) {
      const int i = list->ilist[ii];
      const auto &s = store[i];
      const size_t np = s.size() / (dnum + 1);
      if (np == 0) continue;
      const int *jlist = list->firstneigh[i];
      char *fl = flags_of(i);
      double *val = values_of(i);
      for (int jj = 0; jj < list->numneigh[i]; jj++) {
        const double jtag = (double) tag[jlist[jj] & NEIGHMASK];
        for (size_t m = 0; m < np; m++) {
          if (s[m * (dnum + 1)] == jtag) {
            fl[jj] = 1;
            std::memcpy(&val[(size_t) dnum * jj], &s[m * (dnum + 1) + 1], sizeof(double) * dnum);
            break;
          }
        }
      }
    }
  }
  list_valid = true;
  partners_current = false;
}

void FixViscontactHistory::grow_arrays(int nmax)
{
  if ((int) store.size() < nmax) store.resize(nmax);
  if (ediss.size() < (size_t) nmax * viscontact::NDISS) ediss.resize((size_t) nmax * viscontact::NDISS, 0.0);
  if (eel.size() < (size_t) nmax * viscontact::NELASTIC) eel.resize((size_t) nmax * viscontact::NELASTIC, 0.0);
}

void FixViscontactHistory::copy_arrays(int i, int j, int /*delflag*/)
{
  store[j] = store[i];
  for (int k = 0; k < viscontact::NDISS; k++) ediss[(size_t) j * viscontact::NDISS + k] = ediss[(size_t) i * viscontact::NDISS + k];
  for (int k = 0; k < viscontact::NELASTIC; k++) eel[(size_t) j * viscontact::NELASTIC + k] = eel[(size_t) i * viscontact::NELASTIC + k];
}

void FixViscontactHistory::set_arrays(int i)
{
  store[i].clear();
  for (int k = 0; k < viscontact::NDISS; k++) ediss[(size_t) i * viscontact::NDISS + k] = 0.0;
  for (int k = 0; k < viscontact::NELASTIC; k++) eel[(size_t) i * viscontact::NELASTIC + k] = 0.0;
}

/* Exchange and restart records: [number of partners, partners (tag + dnum values each), the
   atom's NDISS cumulative dissipated energies]. */
int FixViscontactHistory::pack_exchange(int i, double *buf)
{
  const auto &s = store[i];
  buf[0] = (double) (s.size() / (dnum + 1));
  std::memcpy(&buf[1], s.data(), sizeof(double) * s.size());
  int m = 1 + (int) s.size();
  for (int k = 0; k < viscontact::NDISS; k++) buf[m++] = ediss[(size_t) i * viscontact::NDISS + k];
  return m;
}

int FixViscontactHistory::unpack_exchange(int nlocal, double *buf)
{
  const int np = (int) buf[0];
  const int n = np * (dnum + 1);
  store[nlocal].assign(buf + 1, buf + 1 + n);
  for (int k = 0; k < viscontact::NDISS; k++) ediss[(size_t) nlocal * viscontact::NDISS + k] = buf[1 + n + k];
  for (int k = 0; k < viscontact::NELASTIC; k++) eel[(size_t) nlocal * viscontact::NELASTIC + k] = 0.0;
  if (np > maxpartner) {
    maxpartner = np;
    maxexchange = 1 + (dnum + 1) * maxpartner + viscontact::NDISS;
  }
  return 1 + n + viscontact::NDISS;
}

int FixViscontactHistory::pack_restart(int i, double *buf)
{
  // buf[0] = my size (other fixes skip over it), buf[1] = values per contact, buf[2] = number
  // of partners, the partners, the cumulative dissipated energies
  const auto &s = store[i];
  buf[1] = (double) dnum;
  buf[2] = (double) (s.size() / (dnum + 1));
  std::memcpy(&buf[3], s.data(), sizeof(double) * s.size());
  int m = 3 + (int) s.size();
  for (int k = 0; k < viscontact::NDISS; k++) buf[m++] = ediss[(size_t) i * viscontact::NDISS + k];
  buf[0] = m;
  return m;
}

void FixViscontactHistory::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  const int stored_dnum = static_cast<int>(extra[nlocal][m++]);
  if (stored_dnum != dnum)
    error->one(FLERR, "pair viscontact: the restart file's contact history has {} values per "
               "contact, the pair_coeff lines now need {}; use the same sub-models as the run that "
               "wrote it", stored_dnum, dnum);
  const int np = static_cast<int>(extra[nlocal][m++]);
  store[nlocal].assign(&extra[nlocal][m], &extra[nlocal][m] + np * (dnum + 1));
  m += np * (dnum + 1);
  for (int k = 0; k < viscontact::NDISS; k++) ediss[(size_t) nlocal * viscontact::NDISS + k] = extra[nlocal][m++];
  if (np > maxpartner) maxpartner = np;
}

int FixViscontactHistory::size_restart(int nlocal)
{
  return 3 + (int) store[nlocal].size() + viscontact::NDISS;
}

int FixViscontactHistory::maxsize_restart()
{
  update_maxexchange();
  int all = 0;
  MPI_Allreduce(&maxpartner, &all, 1, MPI_INT, MPI_MAX, world);
  return 3 + (dnum + 1) * all + viscontact::NDISS;
}

int FixViscontactHistory::pack_reverse_comm_size(int n, int first)
{
  int m = 0;
  for (int i = first; i < first + n; i++) m += 1 + (int) store[i].size();
  return m;
}

int FixViscontactHistory::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    const auto &s = store[i];
    buf[m++] = (double) (s.size() / (dnum + 1));
    std::memcpy(&buf[m], s.data(), sizeof(double) * s.size());
    m += (int) s.size();
  }
  return m;
}

void FixViscontactHistory::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    const int cnt = (int) buf[m++] * (dnum + 1);
    store[j].insert(store[j].end(), &buf[m], &buf[m] + cnt);
    m += cnt;
  }
}

double FixViscontactHistory::memory_usage()
{
  double bytes = (double) store.size() * sizeof(std::vector<double>);
  for (const auto &s : store) bytes += (double) s.capacity() * sizeof(double);
  bytes += (double) pairval.capacity() * sizeof(double) + (double) pairflag.capacity() +
      (double) offset.capacity() * sizeof(long) +
      (double) (ediss.capacity() + eel.capacity()) * sizeof(double);
  return bytes;
}
