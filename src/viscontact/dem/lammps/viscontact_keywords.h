/* viscontact_keywords.h -- the law keywords shared by `pair viscontact` and
   `fix viscontact/wall`, parsed in one place:

       damping LAW [p P] FORM   [end force|overlap]   tangential TANG
         LAW  = LH | Ts | KK | Li | Hunt | Jian | power      (case-insensitive; power needs p)
         FORM = alpha A vref V [beta B]  |  c0 C [tau S]     (beta / tau: Jian only, required)
         TANG = none | mindlin MU

   Header-only, no LAMMPS includes: every function returns an error message (empty when all is
   well) that the caller turns into one `error->all` line with its own prefix.  Domains:
   A, B, C, S, P, MU >= 0 and finite; V > 0 and finite.  Nothing has a default except
   `end force`.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_KEYWORDS_H
#define VISCONTACT_KEYWORDS_H

#include "viscontact_contact.h"

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace viscontact {

/// Parse a finite number that must be >= 0 (positive = false) or > 0 (positive = true).
/// Returns an error message naming the keyword, or "" on success.
inline std::string parse_number(const std::string &keyword, const std::string &text, bool positive,
                                double &out)
{
  const char *what = positive ? "a finite number > 0" : "a finite number >= 0";
  char *end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(v) ||
      (positive ? !(v > 0.0) : !(v >= 0.0)))
    return keyword + " must be " + what + ", got '" + text + "'";
  out = v;
  return "";
}

/// A material's E (> 0, finite) and nu (in (-1, 0.5], as hertz/material), from their texts;
/// the messages name them E_label and nu_label.  Returns an error message, or "" on success.
inline std::string parse_material(const std::string &E_label, const std::string &nu_label,
                                  const std::string &Etext, const std::string &nutext, double &E,
                                  double &nu)
{
  std::string err = parse_number(E_label, Etext, true, E);
  if (!err.empty()) return err;
  char *end = nullptr;
  nu = std::strtod(nutext.c_str(), &end);
  if (nutext.empty() || *end != '\0' || !(nu > -1.0 && nu <= 0.5))
    return nu_label + " must be in (-1, 0.5], got " + nutext;
  return "";
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
        return fail(err, "unknown damping law '" + args[i + 1] +
                             "'; allowed: LH Ts KK Li Hunt Jian power");
      lp.p = law_exponent(lp.law);
      i += 2;
      // the law's parameters, in any order, up to the next keyword that is not one of them
      while (i < args.size()) {
        const std::string &k = args[i];
        double *slot = nullptr;
        bool *flag = nullptr;
        bool positive = false;
        if (k == "p") slot = &p_in, flag = &has_p;
        else if (k == "alpha") slot = &lp.alpha, flag = &has_alpha;
        else if (k == "vref") slot = &lp.vref, flag = &has_vref, positive = true;
        else if (k == "beta") slot = &lp.beta, flag = &has_beta;
        else if (k == "c0") slot = &lp.c0, flag = &has_c0;
        else if (k == "tau") slot = &lp.tau, flag = &has_tau;
        else break;
        if (*flag) return fail(err, k + " given twice");
        if (i + 1 >= args.size()) return fail(err, k + " needs a value");
        err = parse_number(k, args[i + 1], positive, *slot);
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
        if (i + 2 >= args.size()) return fail(err, "tangential mindlin needs MU (>= 0)");
        err = parse_number("tangential mindlin MU", args[i + 2], false, lp.mu);
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
      if (!has_p) return "damping power needs p P (P >= 0)";
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
      if (jian && !has_beta) return "damping Jian with alpha needs beta B (>= 0)";
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
