/* fix viscontact/wall: sphere-wall contacts with the viscontact laws (skeleton). */
#ifndef VISCONTACT_FIX_WALL_VISCONTACT_H
#define VISCONTACT_FIX_WALL_VISCONTACT_H

#include "fix.h"

namespace LAMMPS_NS {

class FixWallViscontact : public Fix {
 public:
  FixWallViscontact(class LAMMPS *, int, char **);
  ~FixWallViscontact() override;
  int setmask() override;
  void post_force(int) override;
};

}    // namespace LAMMPS_NS

#endif
