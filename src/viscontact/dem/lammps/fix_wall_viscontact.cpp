/* fix viscontact/wall: sphere-wall contacts with the viscontact laws (skeleton). */
#include "fix_wall_viscontact.h"

#include "error.h"

using namespace LAMMPS_NS;

FixWallViscontact::FixWallViscontact(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  error->all(FLERR, "fix viscontact/wall: not implemented yet");
}

FixWallViscontact::~FixWallViscontact() = default;

int FixWallViscontact::setmask()
{
  return FixConst::POST_FORCE;
}

void FixWallViscontact::post_force(int) {}
