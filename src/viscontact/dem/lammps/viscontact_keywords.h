/* viscontact_keywords.h -- the law keywords shared by `pair viscontact` and
   `fix viscontact/wall`, parsed in one place:

       damping LAW [p P] FORM   [end force|overlap]   tangential TANG
         LAW  = LH | Ts | KK | Li | Hunt | Jian | power      (case-insensitive; power needs p)
         FORM = alpha A vref V [beta B]  |  c0 C [tau S]     (beta / tau: Jian only, required)
         TANG = none | mindlin MU

   Header-only, no LAMMPS includes: every function returns an error message (empty when all is
   well) that the caller turns into one `error->all` line with its own prefix.  Domains (the
   Python side's, viscontact/domain.py, where they do not depend on the units style):
     A (alpha) in [0, 1000], B (beta) in [0, 1000], P in [0, 10], MU in [0, 10],
     V (vref) in (0, 1e300], C (c0) and S (tau) in [0, 1e300],
     E in [1e-10, 1e20] (force/area of the units style), NU in (-1, 0.5].
   Every number must parse completely and be finite.  Nothing has a default except
   `end force`.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_KEYWORDS_H
#define VISCONTACT_KEYWORDS_H

#include "viscontact_contact.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace viscontact {

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
  std::string text() const;
};

inline std::string Domain::text() const
{
  return std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + "]";
}

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

/// Accumulates the law keywords of one pair_coeff / wall fix; call take() on each keyword,
/// then finish() once.
class LawKeywords {
 public:
  LawParams lp;

  /// If args[i] is one of `damping`, `end`, `tangential`, consume it with its values, advance
  /// i and return true; otherwise return false and leave i.  err is set on a bad value.
  bool take(const std::vector<std::string> &args, size_t &i, std::string &err)
  {
    const std::string &kw = args[i];
    if (kw == "damping") {
      if (seen_damping) return fail(err, "damping given twice");
      seen_damping = true;
      if (i + 1 >= args.size())
        return fail(err, "damping needs a law: one of LH Ts KK Li Hunt Jian power");
      if (!parse_law(args[i + 1], lp.law))
        return fail(err, "unknown damping law " + quoted(args[i + 1]) +
                             "; allowed: LH Ts KK Li Hunt Jian power");
      lp.p = law_exponent(lp.law);
      i += 2;
      // the law's parameters, in any order, up to the next keyword that is not one of them
      while (i < args.size()) {
        const std::string &k = args[i];
        double *slot = nullptr;
        bool *flag = nullptr;
        const Domain *dom = &PHYSICAL_DOMAIN;
        if (k == "p") slot = &p_in, flag = &has_p, dom = &P_DOMAIN;
        else if (k == "alpha") slot = &lp.alpha, flag = &has_alpha, dom = &ALPHA_DOMAIN;
        else if (k == "vref") slot = &lp.vref, flag = &has_vref, dom = &VREF_DOMAIN;
        else if (k == "beta") slot = &lp.beta, flag = &has_beta, dom = &BETA_DOMAIN;
        else if (k == "c0") slot = &lp.c0, flag = &has_c0;
        else if (k == "tau") slot = &lp.tau, flag = &has_tau;
        else break;
        if (*flag) return fail(err, k + " given twice");
        if (i + 1 >= args.size()) return fail(err, k + " needs a value");
        err = parse_number(k, args[i + 1], *dom, *slot);
        if (!err.empty()) return true;
        *flag = true;
        i += 2;
      }
      return true;
    }
    if (kw == "end") {
      if (seen_end) return fail(err, "end given twice");
      seen_end = true;
      if (i + 1 >= args.size() || (args[i + 1] != "force" && args[i + 1] != "overlap"))
        return fail(err, "end must be followed by force (clamp F_n >= 0, the default) or "
                         "overlap (no clamp)");
      lp.clamp = args[i + 1] == "force";
      i += 2;
      return true;
    }
    if (kw == "tangential") {
      if (seen_tangential) return fail(err, "tangential given twice");
      seen_tangential = true;
      if (i + 1 < args.size() && args[i + 1] == "none") {
        lp.friction = false;
        lp.mu = 0.0;
        i += 2;
        return true;
      }
      if (i + 1 < args.size() && args[i + 1] == "mindlin") {
        if (i + 2 >= args.size()) return fail(err, "tangential mindlin needs MU (in [0, 10])");
        err = parse_number("tangential mindlin MU", args[i + 2], MU_DOMAIN, lp.mu);
        lp.friction = true;
        i += 3;
        return true;
      }
      return fail(err, "tangential must be followed by none or mindlin MU");
    }
    return false;
  }

  /// Check that the keywords form one complete law; "" when they do.
  std::string finish()
  {
    if (!seen_damping) return "missing damping LAW ... (LAW one of LH Ts KK Li Hunt Jian power)";
    if (!seen_tangential) return "missing tangential none | mindlin MU";
    const bool jian = lp.law == Law::Jian;
    if (lp.law == Law::Power) {
      if (!has_p) return "damping power needs p P (P in [0, 10])";
      lp.p = p_in;
    } else if (has_p) {
      return std::string("p is only allowed with damping power, not ") + law_name(lp.law);
    }
    const bool form_alpha = has_alpha || has_vref || has_beta;
    const bool form_c0 = has_c0 || has_tau;
    if (form_alpha && form_c0)
      return "give either alpha A vref V or c0 C, not both";
    if (!form_alpha && !form_c0)
      return std::string("damping ") + law_name(lp.law) + " needs alpha A vref V" +
          (jian ? " beta B" : "") + " or c0 C" + (jian ? " tau S" : "");
    if (form_alpha) {
      if (!has_alpha) return "alpha A is missing (vref V needs it)";
      if (!has_vref) return "vref V (> 0, m/s) is missing (alpha A needs it)";
      if (has_beta && !jian)
        return std::string("beta is only allowed with Jian, not ") + law_name(lp.law);
      if (jian && !has_beta) return "damping Jian with alpha needs beta B (in [0, 1000])";
      lp.by_alpha = true;
    } else {
      if (!has_c0) return "c0 C is missing (tau S needs it)";
      if (has_tau && !jian)
        return std::string("tau is only allowed with Jian, not ") + law_name(lp.law);
      if (jian && !has_tau) return "damping Jian with c0 needs tau S (>= 0, s)";
      lp.by_alpha = false;
    }
    if (!jian) lp.beta = lp.tau = 0.0;
    return "";
  }

 private:
  bool seen_damping = false, seen_end = false, seen_tangential = false;
  bool has_p = false, has_alpha = false, has_vref = false, has_beta = false, has_c0 = false,
       has_tau = false;
  double p_in = 0.0;

  static bool fail(std::string &err, const std::string &msg)
  {
    err = msg;
    return true;
  }
};

}    // namespace viscontact

#endif
