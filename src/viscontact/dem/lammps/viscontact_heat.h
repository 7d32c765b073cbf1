/* viscontact_heat.h -- the heat sub-models: none, or `heat area K` (LAMMPS pair granular's):
   heat flow into i Q = K pi a^2 (T_j - T_i) (K [power/(length^2 temperature)]), j gets -Q.
   Mixing: the geometric mean of K.  No history, no force.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_HEAT_H
#define VISCONTACT_HEAT_H

#include "viscontact_submodel.h"

namespace viscontact {

/// No heat conduction (not a keyword: the default).
struct HeatNone : NoValues<HeatNone>, Absent {
  static constexpr const char *NAME = "none";
  int history_size() const { return 0; }
  VISCONTACT_ALWAYS_INLINE double flow(const ContactState &, const ContactGeometry &) const { return 0.0; }
};

struct HeatArea {
  static constexpr const char *NAME = "area";
  static constexpr int VERSION = 1;
  double k = 0.0;    ///< conductivity K [power/(length^2 temperature)]

  static std::string usage() { return "K"; }
  std::string parse(const Args &args, size_t &i)
  {
    if (i >= args.size()) return "heat area needs K (the conductivity, >= 0)";
    return parse_number("heat area K", args[i++], PHYSICAL_DOMAIN, k);
  }
  static HeatArea mix(const HeatArea &a, const HeatArea &b) { return {detail::geo(a.k, b.k)}; }
  int history_size() const { return 0; }
  static void flip(double *) {}
  std::vector<double> coefficients() const { return {k}; }
  std::string from_coefficients(const std::vector<double> &v)
  {
    std::string err = check_count(NAME, v, 1);
    if (err.empty()) k = v[0];
    return err;
  }
  VISCONTACT_ALWAYS_INLINE double flow(const ContactState &s, const ContactGeometry &g) const
  {
    return k * PI * s.a * s.a * (g.T_j - g.T_i);
  }
};

/// The heat models (the registration: one line per model).
using HeatModel = std::variant<HeatNone, HeatArea>;

}    // namespace viscontact

#endif
