/* viscontact_keywords.h -- the tools every sub-model parses its keywords with (the sub-models
   themselves parse their own words: viscontact_normal.h, viscontact_damping.h, ...):

       damping LAW [p P] FORM   [end force|overlap]   tangential TANG
       [rolling sds KR GAMMAR MUR] [twisting marshall | twisting sds KT GAMMAT MUT] [heat area K]
   and the normal models:
       hertz/material E NU | dmt E NU W | jkr E NU W        (pair_coeff)
       normal hertz | dmt W | jkr W                          (fix viscontact/wall)

   Header-only, no LAMMPS includes: every parser returns an error message (empty when all is
   well) that the caller turns into one `error->all` line with its own prefix.  Domains (the
   Python side's, viscontact/physics/domain.py, where they do not depend on the units style):
     A (alpha) in [0, 1000], B (beta) in [0, 1000], P in [0, 10], MU in [0, 10],
     V (vref) in (0, 1e300], C (c0) and S (tau) in [0, 1e300],
     E in [1e-10, 1e20] (force/area of the units style), NU in (-1, 0.5].
   Every number must parse completely and be finite.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_KEYWORDS_H
#define VISCONTACT_KEYWORDS_H

#include "viscontact_contact.h"
#include "viscontact_native_hints.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <string>
#include <vector>

namespace viscontact {

/// The words of one pair_coeff line or wall fix.
using Args = std::vector<std::string>;

/// A user's token as it goes into an error message: printable ASCII kept, any other byte as
/// \xNN, at most 40 characters (so that a message is one readable line, whatever was typed).
inline std::string quoted(const std::string &text)
{
  std::string out = "'";
  for (unsigned char c : text) {
    if (out.size() > 40) {
      out += "...";
      break;
    }
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    }
  }
  return out + "'";
}

/// The allowed interval of one keyword's value: lo <= x <= hi (lo_open: lo < x).
struct Domain {
  double lo, hi;
  bool lo_open;
  std::string text() const
  {
    return std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + "]";
  }
};

constexpr Domain ALPHA_DOMAIN{0.0, 1000.0, false};    // as viscontact.domain.ALPHA_MAX
constexpr Domain BETA_DOMAIN{0.0, 1000.0, false};     // as viscontact.domain.BETA_MAX
constexpr Domain P_DOMAIN{0.0, 10.0, false};          // as viscontact.domain.P_MAX
constexpr Domain MU_DOMAIN{0.0, 10.0, false};         // as viscontact.domain "friction"
constexpr Domain VREF_DOMAIN{0.0, 1e300, true};
constexpr Domain PHYSICAL_DOMAIN{0.0, 1e300, false};  // c0, tau: any finite value >= 0
constexpr Domain MODULUS_DOMAIN{1e-10, 1e20, false};  // E in any units style's force/area
constexpr Domain POISSON_DOMAIN{-1.0, 0.5, true};
constexpr Domain POSITIVE_DOMAIN{0.0, 1e300, true};   // lengths that must be > 0

/// Parse text as a number inside dom (the whole text must be one finite number).  Returns an
/// error message naming the keyword and the allowed interval, or "" on success.
inline std::string parse_number(const std::string &keyword, const std::string &text,
                                const Domain &dom, double &out)
{
  char *end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  const bool above = dom.lo_open ? v > dom.lo : v >= dom.lo;
  if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(v) || !above ||
      !(v <= dom.hi))
    return keyword + " must be a finite number in " + dom.text() + ", got " + quoted(text);
  out = v;
  return "";
}

/// Parse the values args[i], args[i + 1], ... named `names` (each in its domain) into `out`,
/// stopping at the first error; the messages name them `prefix + name`.
inline std::string parse_numbers(const Args &args, size_t i, const std::string &prefix,
                                 std::initializer_list<const char *> names,
                                 std::initializer_list<const Domain *> domains,
                                 std::initializer_list<double *> out)
{
  auto name = names.begin();
  auto dom = domains.begin();
  for (double *slot : out) {
    const std::string err = parse_number(prefix + *name++, args[i++], **dom++, *slot);
    if (!err.empty()) return err;
  }
  return "";
}

/// True when the whole text is one number (a test for optional values, no domain).
inline bool is_number(const std::string &x)
{
  char *end = nullptr;
  std::strtod(x.c_str(), &end);
  return !x.empty() && end != x.c_str() && *end == '\0';
}

/// A material's E (MODULUS_DOMAIN) and nu (in (-1, 0.5], as hertz/material), from their texts;
/// the messages name them E_label and nu_label.  Returns an error message, or "" on success.
inline std::string parse_material(const std::string &E_label, const std::string &nu_label,
                                  const std::string &Etext, const std::string &nutext, double &E,
                                  double &nu)
{
  std::string err = parse_number(E_label, Etext, MODULUS_DOMAIN, E);
  if (!err.empty()) return err;
  return parse_number(nu_label, nutext, POISSON_DOMAIN, nu);
}

/// "a, b or c" (sep ", " and last " or "), for the lists of alternatives in messages.
inline std::string join_alternatives(const std::vector<std::string> &items,
                                     const std::string &sep = ", ",
                                     const std::string &last = " or ")
{
  std::string out;
  for (size_t k = 0; k < items.size(); k++)
    out += (k == 0 ? "" : k + 1 == items.size() ? last : sep) + items[k];
  return out;
}

}    // namespace viscontact

#endif
