/* viscontact_damping.h -- the damping sub-model: one of the viscoelastic laws of
   viscontact_contact.h (LH Ts KK Li Hunt Jian power), with its keywords

       damping LAW [p P] FORM [end force|overlap]
         FORM = alpha A vref V [beta B]  |  c0 C [tau S]        (beta / tau: Jian only, required)

   F_d = c0 g(t_c) delta_a^p ddelta, ddelta = -v_n, F_n = F_ne + F_d (clamped at 0 with
   `end force`, the default with hertz; dmt and jkr take `end overlap` only); c0 and tau per
   contact from the law (contact_coeffs).  History: Jian's relaxation g = 1 - exp(-t_c/tau) at
   the last step (1 value, laws with a relaxation time; format-2 restarts held the start time t0
   there, converted on reading: PairViscontact::convert_format2).  Mixing: the law, its p and its form must agree; every number
   the geometric mean; the clamp if either type clamps (native's larger limit_damping).

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_DAMPING_H
#define VISCONTACT_DAMPING_H

#include "viscontact_submodel.h"

namespace viscontact {

struct DampingLaw {
  static constexpr const char *NAME = "damping";
  static constexpr int VERSION = 1;
  LawParams law;

  bool relaxes() const { return LAW_TABLE[static_cast<int>(law.law)].needs_beta; }
  int history_size() const { return relaxes() ? 1 : 0; }
  static void flip(double *) {}

  /// Per-contact k_H, c0, tau of a contact with m* and R*, and the contact's E*.
  ContactCoeffs coeffs(double Estar, double meff, double reff) const
  {
    return contact_coeffs(law, Estar, meff, reff);
  }

  /// The types' laws mixed; false (and `what` the differing part) when they cannot be.
  static bool mix(const DampingLaw &a, const DampingLaw &b, DampingLaw &m, std::string &what)
  {
    if (a.law.law != b.law.law || a.law.p != b.law.p) what = "damping law";
    else if (a.law.by_alpha != b.law.by_alpha) what = "damping form (alpha or c0)";
    if (!what.empty()) return false;
    using detail::geo;
    m = a;
    LawParams &l = m.law;
    l.alpha = geo(a.law.alpha, b.law.alpha);
    l.vref = geo(a.law.vref, b.law.vref);
    l.beta = geo(a.law.beta, b.law.beta);
    l.c0 = geo(a.law.c0, b.law.c0);
    l.tau = geo(a.law.tau, b.law.tau);
    l.clamp = a.law.clamp || b.law.clamp;    // native: the larger limit_damping
    return true;
  }

  /// Restart record "damping LAW": p, form, alpha, vref, beta, c0, tau, clamp.
  Record record() const
  {
    const LawParams &l = law;
    return {std::string(NAME) + " " + law_name(l.law), VERSION,
            {l.p, l.by_alpha ? 1.0 : 0.0, l.alpha, l.vref, l.beta, l.c0, l.tau, l.clamp ? 1.0 : 0.0}};
  }
  std::string from_record(const Record &r)
  {
    const std::string head = std::string(NAME) + " ";
    if (r.name.compare(0, head.size(), head) != 0 || !parse_law(r.name.substr(head.size()), law.law))
      return "restart record " + quoted(r.name) + " is not a damping law";
    if (r.version < 1 || r.version > VERSION)
      return "restart record " + r.name + " has version " + std::to_string(r.version) +
          "; this viscontact reads versions 1 to " + std::to_string(VERSION);
    std::string err = check_count("damping", r.values, 8);
    if (!err.empty()) return err;
    const double *v = r.values.data();
    law.p = v[0];
    law.by_alpha = v[1] != 0.0;
    law.alpha = v[2];
    law.vref = v[3];
    law.beta = v[4];
    law.c0 = v[5];
    law.tau = v[6];
    law.clamp = v[7] != 0.0;
    return "";
  }

  /// A new contact: Jian's relaxation g = 1 - exp(-t_c/tau) with its clock started at most one
  /// step back (contact_start_time): one expm1 per new contact (h: this sub-model's history,
  /// nullptr if none; s.cc set).
  VISCONTACT_ALWAYS_INLINE void start(const ContactState &s, double *h) const
  {
    if (h && s.cc->tau > 0.0)
      h[0] = relaxation(s.t_now - contact_start_time(s.t_now, s.dt, s.delta, -s.vn), s.cc->tau);
  }

  /// A contact of a format-2 restart (viscontact before 2026-11-27: its slot held the contact's
  /// start time t0): its relaxation now, g = 1 - exp(-(t_now - t0)/tau), the value the old
  /// plugin would compute at t_now (h: this sub-model's history, nullptr if none).
  static void from_start_time(double *h, double tau, double t_now)
  {
    if (h && tau > 0.0) h[0] = relaxation(t_now > h[0] ? t_now - h[0] : 0.0, tau);
  }

  /// eta_n = c0 g delta_a^p, F_n = F_ne + eta_n ddelta (clamped).  h: Jian's g, nullptr if none
  /// kept.  Each regular step advances g exactly, g <- g exp(-dt/tau) + 1 - exp(-dt/tau),
  /// whatever dt is at that step (the factors cached per coefficient set and dt:
  /// relaxation_step, s.cc's for s.dt); a run's setup and single() (advance false) read g as it is.
  VISCONTACT_ALWAYS_INLINE void calculate(ContactState &s, double *h) const
  {
    double grel = 1.0;
    if (h && s.cc->tau > 0.0) {
      if (s.advance && !s.fresh) h[0] = h[0] * s.cc->decay + s.cc->rise;
      grel = h[0];
    }
    s.eta_n = s.cc->c0 * grel * law_overlap_power(law.law, s.delta_a, law.p);
    const double fd = s.eta_n * -s.vn;
    s.fn = s.fne + fd;
    if (law.clamp && s.fn < 0.0) s.fn = 0.0;
  }
};

/// The damping keywords of one pair_coeff line or wall fix: take() each `damping` and `end`,
/// then finish() once.
class DampingKeywords {
 public:
  /// Consume `damping ...` or `end ...` at args[i] (true), or leave i (false).
  bool take(const Args &args, size_t &i, DampingLaw &d, std::string &err)
  {
    LawParams &lp = d.law;
    const std::string &kw = args[i];
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
    if (kw != "damping") return false;
    if (seen_damping) return fail(err, "damping given twice");
    seen_damping = true;
    if (i + 1 >= args.size()) return fail(err, "damping needs a law: one of " + law_names());
    if (!parse_law(args[i + 1], lp.law))
      return fail(err, "unknown damping law " + quoted(args[i + 1]) + "; allowed: " + law_names() +
                         native_hint(args, i + 1));
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

  /// "" when a `damping` keyword was given.
  std::string check_given() const
  {
    return seen_damping ? "" : "missing damping LAW ... (LAW one of " + law_names() + ")";
  }

  /// The clamp with the normal model: dmt and jkr (cohesive, `normal_name`) take no clamp.
  std::string check_end(DampingLaw &d, bool cohesive, const std::string &normal_name) const
  {
    if (!cohesive) return "";
    if (seen_end && d.law.clamp)
      return "end force is not allowed with the cohesive normal model " + normal_name +
          " (use end overlap, the default)";
    d.law.clamp = false;
    return "";
  }

  /// Check that the keywords form one complete law ("" when they do): p, then the form.
  std::string finish(DampingLaw &d)
  {
    LawParams &lp = d.law;
    const std::string name = law_name(lp.law);
    if (law_exponent(lp.law) < 0.0) {
      if (!has_p) return "damping " + name + " needs p P (P in [0, 10])";
      lp.p = p_in;
    } else if (has_p) {
      return "p is only allowed with damping " + std::string(law_name(Law::Power)) + ", not " + name;
    }
    return finish_form(d);
  }

 private:
  bool seen_damping = false, seen_end = false;
  bool has_p = false, has_alpha = false, has_vref = false, has_beta = false, has_c0 = false,
       has_tau = false;
  double p_in = 0.0;

  static bool fail(std::string &err, const std::string &msg)
  {
    err = msg;
    return true;
  }

  /// The damping form: alpha A vref V [beta B] or c0 C [tau S].
  std::string finish_form(DampingLaw &d)
  {
    LawParams &lp = d.law;
    const bool jian = d.relaxes();
    const std::string name = law_name(lp.law);
    const bool form_alpha = has_alpha || has_vref || has_beta;
    const bool form_c0 = has_c0 || has_tau;
    if (form_alpha && form_c0) return "give either alpha A vref V or c0 C, not both";
    if (!form_alpha && !form_c0)
      return "damping " + name + " needs alpha A vref V" + (jian ? " beta B" : "") + " or c0 C" +
          (jian ? " tau S" : "");
    if (form_alpha) {
      if (!has_alpha) return "alpha A is missing (vref V needs it)";
      if (!has_vref) return "vref V (> 0, m/s) is missing (alpha A needs it)";
      if (has_beta && !jian) return "beta is only allowed with " + beta_law_names() + ", not " + name;
      if (jian && !has_beta) return "damping " + name + " with alpha needs beta B (in [0, 1000])";
      lp.by_alpha = true;
    } else {
      if (!has_c0) return "c0 C is missing (tau S needs it)";
      if (has_tau && !jian) return "tau is only allowed with " + beta_law_names() + ", not " + name;
      if (jian && !has_tau) return "damping " + name + " with c0 needs tau S (>= 0, s)";
      lp.by_alpha = false;
    }
    if (!jian) lp.beta = lp.tau = 0.0;
    return "";
  }
};

}    // namespace viscontact

#endif
