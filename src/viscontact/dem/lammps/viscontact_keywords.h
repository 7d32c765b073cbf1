/* viscontact_keywords.h -- the law keywords shared by `pair viscontact` and
   `fix viscontact/wall`, parsed in one place:

       damping LAW [p P] FORM   [end force|overlap]   tangential TANG
       [rolling sds KR GAMMAR MUR] [twisting marshall | twisting sds KT GAMMAT MUT] [heat area K]
         LAW  = LH | Ts | KK | Li | Hunt | Jian | power      (case-insensitive; power needs p)
         FORM = alpha A vref V [beta B]  |  c0 C [tau S]     (beta / tau: Jian only, required)
         TANG = none | linear_nohistory XGAMMA MU | linear_history KT XGAMMA MU
              | mindlin KT|NULL XGAMMA MU | mindlin MU (= mindlin NULL 0 MU)
              | mindlin_rescale | mindlin/force | mindlin_rescale/force  KT|NULL XGAMMA MU
   and the normal models (parse_normal, parse_wall_normal):
       hertz/material E NU | dmt E NU W | jkr E NU W        (pair_coeff)
       normal hertz | dmt W | jkr W                          (fix viscontact/wall)
   `end` defaults to force with hertz, overlap with dmt/jkr (where force is an error).

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
#include "viscontact_model.h"
#include "viscontact_native_hints.h"

#include <array>
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

/// The NORMAL model of a pair_coeff line starting at args[i]: `hertz/material E NU`,
/// `dmt E NU W` or `jkr E NU W`; advances i past it.  Returns an error message, or "".
inline std::string parse_normal(const std::vector<std::string> &args, size_t &i, NormalParams &np,
                                double &E, double &nu)
{
  const std::string model = i < args.size() ? args[i] : "";
  const bool cohesive = model == "dmt" || model == "jkr";
  if (model != "hertz/material" && !cohesive)
    return "expected 'hertz/material E NU', 'dmt E NU W' or 'jkr E NU W' after the two types, got " +
        quoted(model) + native_hint(args, i);
  const size_t nval = cohesive ? 3 : 2;
  if (i + nval >= args.size())
    return model + (cohesive ? " needs three values, E NU W" : " needs two values, E and NU");
  std::string err = parse_material("E", "nu", args[i + 1], args[i + 2], E, nu);
  if (!err.empty()) return err + native_hint(args, i);
  np.kind = model == "dmt" ? NormalKind::DMT : model == "jkr" ? NormalKind::JKR : NormalKind::Hertz;
  np.W = 0.0;
  if (cohesive) {
    err = parse_number(model + " W", args[i + 3], PHYSICAL_DOMAIN, np.W);
    if (!err.empty()) return err;
  }
  i += nval + 1;
  return "";
}

/// The wall's `normal hertz | dmt W | jkr W` at args[i] (the keyword itself); advances i.
inline std::string parse_wall_normal(const std::vector<std::string> &args, size_t &i,
                                     NormalParams &np)
{
  const std::string model = i + 1 < args.size() ? args[i + 1] : "";
  if (model == "hertz") {
    np.kind = NormalKind::Hertz;
    np.W = 0.0;
    i += 2;
    return "";
  }
  if (model != "dmt" && model != "jkr")
    return "normal must be followed by hertz, dmt W or jkr W, got " + quoted(model);
  if (i + 2 >= args.size()) return "normal " + model + " needs W";
  np.kind = model == "dmt" ? NormalKind::DMT : NormalKind::JKR;
  std::string err = parse_number("normal " + model + " W", args[i + 2], PHYSICAL_DOMAIN, np.W);
  if (!err.empty()) return err;
  i += 3;
  return "";
}

/// Accumulates the law keywords of one pair_coeff / wall fix; call take() on each keyword,
/// then finish() once.
class LawKeywords {
 public:
  LawParams lp;
  TangentialParams tangential;
  RollingParams rolling;
  TwistingParams twisting;
  HeatParams heat;

  /// The contact model of these keywords with the given normal model (E*, G* to be set by the
  /// caller, then setup()).
  ContactModel model(const NormalParams &normal) const
  {
    ContactModel m;
    m.normal = normal;
    m.law = lp;
    m.tangential = tangential;
    m.rolling = rolling;
    m.twisting = twisting;
    m.heat = heat;
    m.setup();
    return m;
  }

  /// If args[i] is one of `damping`, `end`, `tangential`, `rolling`, `twisting`, `heat`, consume it with its values, advance
  /// i and return true; otherwise return false and leave i.  err is set on a bad value.
  bool take(const std::vector<std::string> &args, size_t &i, std::string &err)
  {
    const std::string &kw = args[i];
    if (kw == "damping") {
      if (seen_damping) return fail(err, "damping given twice");
      seen_damping = true;
      if (i + 1 >= args.size())
        return fail(err, "damping needs a law: one of " + law_names());
      if (!parse_law(args[i + 1], lp.law))
        return fail(err, "unknown damping law " + quoted(args[i + 1]) +
                             "; allowed: " + law_names() + native_hint(args, i + 1));
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
      const std::string model = i + 1 < args.size() ? args[i + 1] : "";
      TangentialParams &t = tangential;
      auto is_number = [](const std::string &x) {
        char *end = nullptr;
        std::strtod(x.c_str(), &end);
        return !x.empty() && end != x.c_str() && *end == '\0';
      };
      if (model == "none") {
        t.kind = TangentialKind::None;
        i += 2;
      } else if (model == "linear_nohistory") {
        if (i + 3 >= args.size()) return fail(err, "tangential linear_nohistory needs XGAMMA MU");
        t.kind = TangentialKind::LinearNoHistory;
        err = parse_number("tangential linear_nohistory XGAMMA", args[i + 2], PHYSICAL_DOMAIN, t.xgamma);
        if (err.empty()) err = parse_number("tangential linear_nohistory MU", args[i + 3], MU_DOMAIN, t.mu);
        i += 4;
      } else if (model == "linear_history") {
        if (i + 4 >= args.size()) return fail(err, "tangential linear_history needs KT XGAMMA MU");
        t.kind = TangentialKind::LinearHistory;
        err = parse_number("tangential linear_history KT", args[i + 2], PHYSICAL_DOMAIN, t.kt);
        if (err.empty()) err = parse_number("tangential linear_history XGAMMA", args[i + 3], PHYSICAL_DOMAIN, t.xgamma);
        if (err.empty()) err = parse_number("tangential linear_history MU", args[i + 4], MU_DOMAIN, t.mu);
        i += 5;
      } else if (model == "mindlin" || model == "mindlin_rescale" || model == "mindlin/force" ||
                 model == "mindlin_rescale/force") {
        t.kind = model == "mindlin" ? TangentialKind::Mindlin
            : model == "mindlin_rescale" ? TangentialKind::MindlinRescale
            : model == "mindlin/force" ? TangentialKind::MindlinForce
                                       : TangentialKind::MindlinRescaleForce;
        const bool long_form = i + 4 < args.size() &&
            (args[i + 2] == "NULL" || is_number(args[i + 2])) && is_number(args[i + 3]) &&
            is_number(args[i + 4]);
        if (model == "mindlin" && !long_form) {
          // the short form `mindlin MU` = `mindlin NULL 0 MU`
          if (i + 2 >= args.size()) return fail(err, "tangential mindlin needs MU (in [0, 10]) or KT|NULL XGAMMA MU");
          t.kt_null = true;
          t.xgamma = 0.0;
          err = parse_number("tangential mindlin MU", args[i + 2], MU_DOMAIN, t.mu);
          i += 3;
        } else {
          if (!long_form)
            return fail(err, "tangential " + model + " needs KT|NULL XGAMMA MU (three numbers)");
          const std::string pre = "tangential " + model + " ";
          t.kt_null = args[i + 2] == "NULL";
          if (!t.kt_null) err = parse_number(pre + "KT", args[i + 2], PHYSICAL_DOMAIN, t.kt);
          if (err.empty()) err = parse_number(pre + "XGAMMA", args[i + 3], PHYSICAL_DOMAIN, t.xgamma);
          if (err.empty()) err = parse_number(pre + "MU", args[i + 4], MU_DOMAIN, t.mu);
          i += 5;
        }
      } else {
        return fail(err, "tangential must be followed by none or mindlin MU, or linear_nohistory "
                         "XGAMMA MU, linear_history KT XGAMMA MU, mindlin KT|NULL XGAMMA MU, "
                         "mindlin_rescale, mindlin/force, mindlin_rescale/force KT|NULL XGAMMA MU; "
                         "got " + quoted(model));
      }
      // legacy fields (callers that know only `mindlin MU`)
      lp.friction = t.kind != TangentialKind::None;
      lp.mu = t.mu;
      return true;
    }
    if (kw == "rolling") {
      if (seen_rolling) return fail(err, "rolling given twice");
      seen_rolling = true;
      if (i + 1 >= args.size() || args[i + 1] != "sds")
        return fail(err, "rolling must be followed by sds KR GAMMAR MUR");
      rolling.kind = RollingKind::SDS;
      return take_sds(args, i, "rolling", {"KR", "GAMMAR", "MUR"}, MU_DOMAIN, rolling.k,
                      rolling.gamma, rolling.mu, err);
    }
    if (kw == "twisting") {
      if (seen_twisting) return fail(err, "twisting given twice");
      seen_twisting = true;
      const std::string model = i + 1 < args.size() ? args[i + 1] : "";
      if (model == "marshall") {
        twisting.kind = TwistingKind::Marshall;
        i += 2;
        return true;
      }
      if (model != "sds") return fail(err, "twisting must be followed by marshall or sds KT GAMMAT MUT");
      twisting.kind = TwistingKind::SDS;
      return take_sds(args, i, "twisting", {"KT", "GAMMAT", "MUT"}, PHYSICAL_DOMAIN, twisting.k,
                      twisting.gamma, twisting.mu, err);
    }
    if (kw == "heat") {
      if (seen_heat) return fail(err, "heat given twice");
      seen_heat = true;
      if (i + 1 >= args.size() || args[i + 1] != "area")
        return fail(err, "heat must be followed by area K");
      if (i + 2 >= args.size()) return fail(err, "heat area needs K (the conductivity, >= 0)");
      heat.kind = HeatKind::Area;
      err = parse_number("heat area K", args[i + 2], PHYSICAL_DOMAIN, heat.k);
      i += 3;
      return true;
    }
    return false;
  }

  /// Check that the keywords form one complete law; "" when they do.
  std::string finish(NormalKind normal_kind = NormalKind::Hertz)
  {
    if (!seen_damping) return "missing damping LAW ... (LAW one of " + law_names() + ")";
    if (!seen_tangential)
      return "missing tangential none | mindlin MU | linear_nohistory XGAMMA MU | linear_history KT "
             "XGAMMA MU | mindlin[_rescale][/force] KT|NULL XGAMMA MU (one is required)";
    if (normal_kind != NormalKind::Hertz) {
      if (seen_end && lp.clamp)
        return std::string("end force is not allowed with the cohesive normal model ") +
            (normal_kind == NormalKind::DMT ? "dmt" : "jkr") + " (use end overlap, the default)";
      lp.clamp = false;
    }
    if (twisting.kind == TwistingKind::Marshall && (tangential.kind == TangentialKind::None ||
                                                    tangential.kind == TangentialKind::LinearNoHistory))
      return "twisting marshall needs a tangential spring: linear_history or a mindlin model";
    const bool jian = LAW_TABLE[static_cast<int>(lp.law)].needs_beta;
    if (law_exponent(lp.law) < 0.0) {
      if (!has_p) return std::string("damping ") + law_name(lp.law) + " needs p P (P in [0, 10])";
      lp.p = p_in;
    } else if (has_p) {
      return "p is only allowed with damping " + std::string(law_name(Law::Power)) + ", not " +
          law_name(lp.law);
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
        return "beta is only allowed with " + beta_law_names() + ", not " + law_name(lp.law);
      if (jian && !has_beta)
        return std::string("damping ") + law_name(lp.law) + " with alpha needs beta B (in [0, 1000])";
      lp.by_alpha = true;
    } else {
      if (!has_c0) return "c0 C is missing (tau S needs it)";
      if (has_tau && !jian)
        return "tau is only allowed with " + beta_law_names() + ", not " + law_name(lp.law);
      if (jian && !has_tau)
        return std::string("damping ") + law_name(lp.law) + " with c0 needs tau S (>= 0, s)";
      lp.by_alpha = false;
    }
    if (!jian) lp.beta = lp.tau = 0.0;
    return "";
  }

 private:
  bool seen_damping = false, seen_end = false, seen_tangential = false, seen_rolling = false,
       seen_twisting = false, seen_heat = false;
  bool has_p = false, has_alpha = false, has_vref = false, has_beta = false, has_c0 = false,
       has_tau = false;
  double p_in = 0.0;

  static bool fail(std::string &err, const std::string &msg)
  {
    err = msg;
    return true;
  }

  /// `WHAT sds K GAMMA MU` at args[i] (rolling or twisting, names: the three values' names in
  /// the messages): K > 0, GAMMA >= 0, MU in mu_domain; advances i past it and returns true
  /// (as take()), err set on a missing or bad value.
  static bool take_sds(const std::vector<std::string> &args, size_t &i, const std::string &what,
                       const std::array<const char *, 3> &names, const Domain &mu_domain,
                       double &k, double &gamma, double &mu, std::string &err)
  {
    const std::string head = what + " sds ";
    if (i + 4 >= args.size())
      return fail(err, head + "needs " + names[0] + " " + names[1] + " " + names[2]);
    err = parse_number(head + names[0], args[i + 2], POSITIVE_DOMAIN, k);
    if (err.empty()) err = parse_number(head + names[1], args[i + 3], PHYSICAL_DOMAIN, gamma);
    if (err.empty()) err = parse_number(head + names[2], args[i + 4], mu_domain, mu);
    i += 5;
    return true;
  }
};

}    // namespace viscontact

#endif
