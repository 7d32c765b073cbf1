/* viscontact_native_hints.h -- what a word of native `pair_style granular` / `fix wall/gran`
   means in a viscontact line.

   A user coming from native LAMMPS types its words: `damping tsuji`, `hertz/material E DAMP NU`,
   `limit_damping`.  native_hint() turns such a word, where viscontact's parser stopped on it,
   into the viscontact equivalent, appended to the one ERROR line.  The equivalences are those of
   the documentation page "Coming from native LAMMPS granular" (docs/native.md), each measured
   side by side on the pinned LAMMPS (stable 22 Jul 2025):
     damping velocity        eta = eta0              = LH c0 eta0 (exact, any sizes)
     damping mass_velocity   eta = eta0 m*           = LH c0 (eta0 m*) for one m*
     damping viscoelastic    eta = eta0 m* a         = KK c0 (eta0 m* sqrt(R*)) for one m*, R*
     damping tsuji           eta = alpha_T sqrt(m* k_H) delta^(1/4)
                                                     = Ts alpha alpha_T vref V (any sizes)
     damping coeff_restitution  = tsuji with alpha from e; viscontact dem coeff --law Ts --e E
                                  --end overlap gives the same alpha, exact
     limit_damping              = end force (the default with hertz/material)

   Header-only, no LAMMPS includes.  This file is part of viscontact.  Compiled into a LAMMPS
   plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_NATIVE_HINTS_H
#define VISCONTACT_NATIVE_HINTS_H

#include <cstdlib>
#include <string>
#include <vector>

namespace viscontact {

namespace native_detail {

struct Hint {
  const char *word;
  const char *text;
};

// native word -> what to write instead (docs/native.md, "Keyword by keyword")
constexpr Hint HINTS[] = {
    {"tsuji", "native damping tsuji is law Ts: 'damping Ts alpha A vref V' with A native's "
              "alpha_T(e), exact for any sizes and masses; or 'viscontact dem coeff --law Ts "
              "--e E --vref V' for an exact e at V"},
    {"coeff_restitution", "native damping coeff_restitution is law Ts with the zero-overlap "
                          "end: 'damping Ts alpha A vref V end overlap', A from 'viscontact dem "
                          "coeff --law Ts --e E --vref V --end overlap' (native's alpha, exactly)"},
    {"viscoelastic", "native damping viscoelastic (eta0 m* a) is law KK: 'damping KK c0 C' with "
                     "C = eta0 m* sqrt(R*) (exact for one m* and R*), or 'damping KK alpha A "
                     "vref V' for the same e at V in every pair"},
    {"mass_velocity", "native damping mass_velocity (eta0 m*) is law LH: 'damping LH c0 C' with "
                      "C = eta0 m* (exact for one m*), or 'damping LH alpha A vref V' for the "
                      "same e at V in every pair"},
    {"velocity", "native damping velocity (eta0) is law LH: 'damping LH c0 C' with C = eta0, "
                 "exact for any sizes"},
    {"limit_damping", "native limit_damping is 'end force' (the default with hertz/material)"},
    {"hooke", "viscontact's spring is Hertz: 'hertz/material E NU', 'dmt E NU W' or "
              "'jkr E NU W'; native hooke has no viscontact equivalent"},
    {"hooke/stiffness", "viscontact's spring is Hertz: 'hertz/material E NU', 'dmt E NU W' or "
                        "'jkr E NU W'; native hooke/stiffness has no viscontact equivalent"},
    {"hertz", "native hertz K DAMP takes a stiffness; viscontact takes the material: "
              "'hertz/material E NU' (k_Hertz = (4/3) E* sqrt(R*))"},
    {"synchronized_verlet", "native synchronized_verlet is not offered by viscontact"},
};

inline bool is_number(const std::string &x)
{
  char *end = nullptr;
  std::strtod(x.c_str(), &end);
  return !x.empty() && end != x.c_str() && *end == '\0';
}

// the normal model's word that args[i] belongs to (args[k] with numbers only from k+1 to i),
// or args.size() if none
inline size_t normal_word(const std::vector<std::string> &args, size_t i)
{
  for (size_t k = i + 1; k-- > 0;) {
    const std::string &w = args[k];
    if (w == "hertz/material" || w == "dmt" || w == "jkr") return k;
    if (!is_number(w)) break;
  }
  return args.size();
}

}  // namespace native_detail

/// A hint for args[i], the word a viscontact parser stopped on, when it reads as native
/// `pair_style granular` / `fix wall/gran` syntax: "; <what to write instead>" to append to the
/// error message, or "" when args[i] means nothing in native.  A native normal model with its
/// damping coefficient (`hertz/material E DAMP NU`, `dmt|jkr E DAMP NU W`: one number more than
/// viscontact's) is recognised from args[i] being the model's word or one of its numbers.
inline std::string native_hint(const std::vector<std::string> &args, size_t i)
{
  if (i >= args.size()) return "";
  for (const auto &h : native_detail::HINTS)
    if (args[i] == h.word) return std::string("; ") + h.text;
  const size_t k = native_detail::normal_word(args, i);
  if (k >= args.size()) return "";
  size_t n = 0;
  while (k + 1 + n < args.size() && native_detail::is_number(args[k + 1 + n])) ++n;
  const bool cohesive = args[k] != "hertz/material";
  if (n != (cohesive ? 4u : 3u)) return "";
  return "; this reads as native " + args[k] + (cohesive ? " E DAMP NU W" : " E DAMP NU") +
      ": viscontact's " + args[k] + " takes " + (cohesive ? "E NU W" : "E NU") +
      " and no damping coefficient (the damping is the 'damping LAW ...' keyword)";
}

}  // namespace viscontact

#endif  // VISCONTACT_NATIVE_HINTS_H
