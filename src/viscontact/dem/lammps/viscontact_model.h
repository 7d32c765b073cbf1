/* viscontact_model.h -- THE contact step of viscontact: one granular contact model per type pair
   (pair viscontact) or per wall type (fix viscontact/wall), composed of one sub-model of each
   kind, as LAMMPS's GranularModel of its GranSubMods:

     normal      hertz/material E NU | dmt E NU W | jkr E NU W       viscontact_normal.h
     damping     LAW [p P] FORM [end force|overlap]                  viscontact_damping.h
     tangential  none | linear_nohistory | linear_history | mindlin...  viscontact_tangential.h
     rolling     none | sds KR GAMMAR MUR                            viscontact_rolling.h
     twisting    none | marshall | sds KT GAMMAT MUT                 viscontact_twisting.h
     heat        none | area K                                       viscontact_heat.h

   Each sub-model owns its keywords and their domains, its coefficients and their mixing, its
   history values and their i <-> j signs, its restart record and its force; a kind is a
   std::variant of its models, visited by an inlined index test (no virtual call per contact).
   Order of one evaluation (as LAMMPS pair granular, stable 22Jul2025): contact radius a and
   elastic normal force F_ne (normal), damping prefactor eta_n and F_n = F_ne + F_d (damping),
   critical force F0 (normal), tangential force and its torques, rolling, twisting, heat; then
   the energy count (viscontact_energy.h).

   History of one contact: touch flag, the damping's values, the energy count's (track_energy),
   then the tangential, rolling and twisting models' values.  A pair style lays every type pair
   out alike (HistoryLayout: the largest block of each kind), so one size and one sign rule serve
   all its contacts.

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_MODEL_H
#define VISCONTACT_MODEL_H

#include "viscontact_damping.h"
#include "viscontact_energy.h"
#include "viscontact_heat.h"
#include "viscontact_normal.h"
#include "viscontact_rolling.h"
#include "viscontact_tangential.h"
#include "viscontact_twisting.h"

#include <algorithm>
#include <string>
#include <vector>

namespace viscontact {

/// History values per kind of sub-model; a pair style takes the largest of each over its type
/// pairs (merge), so that all its contacts share one layout.
struct HistoryLayout {
  int damping = 0, tangential = 0, rolling = 0, twisting = 0;
  void merge(const HistoryLayout &o)
  {
    damping = std::max(damping, o.damping);
    tangential = std::max(tangential, o.tangential);
    rolling = std::max(rolling, o.rolling);
    twisting = std::max(twisting, o.twisting);
  }
};

class ContactModel {
 public:
  NormalModel normal;
  DampingLaw damping;
  TangentialModel tangential;
  RollingModel rolling;
  TwistingModel twisting;
  HeatModel heat;
  double Estar = 0.0, Gstar = 0.0;    ///< the contact's effective Young and shear moduli
  /// Count energies (dissipated by mechanism, elastic parts, per-contact history slots).  Off,
  /// the step skips that bookkeeping (the forces are the same) and ContactResult's energy
  /// fields are 0.  Set before setup().
  bool track_energy = true;

  /// E* and G* of the contact (pair: of the two materials; wall: particle and wall).
  void set_moduli(double E, double G)
  {
    Estar = E;
    Gstar = G;
  }

  /// The history values each kind of this model keeps.
  HistoryLayout layout() const
  {
    HistoryLayout l;
    l.damping = damping.history_size();
    dispatch(tangential, [&](const auto &m) { l.tangential = m.history_size(); });
    dispatch(rolling, [&](const auto &m) { l.rolling = m.history_size(); });
    dispatch(twisting, [&](const auto &m) { l.twisting = m.history_size(); });
    return l;
  }

  /// Lay out the history slots; call after the sub-models are set (and after mixing).  at_least:
  /// blocks reserved even if this model does not use them (a pair style's common layout).
  void setup(const HistoryLayout &at_least = HistoryLayout())
  {
    HistoryLayout l = layout();
    l.merge(at_least);
    int n = 1;
    slots = HistorySlots();
    auto block = [&n](int size, int &offset) {
      if (size > 0) offset = n;
      n += size;
    };
    block(l.damping, slots.damping);
    if (track_energy) {
      block(1, slots.energy);
      block(NELASTIC, slots.elastic);
      block(NDAMP, slots.damp);
    }
    block(l.tangential, slots.tangential);
    block(l.rolling, slots.rolling);
    block(l.twisting, slots.twisting);
    slots.size = n;
  }
  int history_size() const { return slots.size; }
  const HistorySlots &history_slots() const { return slots; }

  /// Set to -1 the sign of each history slot this model negates when a pair's stored
  /// orientation flips (i <-> j), leaving the others as they are (so the signs of several type
  /// pairs of one layout combine); the caller starts from +1.
  void history_signs(double *sign) const
  {
    // the tangential displacement flips (n and v_t do); the rolling and twisting displacements
    // keep their sign (both factors of their rates flip; native pair granular negates them too,
    // which corrupts a contact whose pair order changes at a rebuild, migration or restart)
    dispatch(tangential, [&](const auto &m) { if (slots.tangential >= 0) m.flip(sign + slots.tangential); });
    dispatch(rolling, [&](const auto &m) { if (slots.rolling >= 0) m.flip(sign + slots.rolling); });
    dispatch(twisting, [&](const auto &m) { if (slots.twisting >= 0) m.flip(sign + slots.twisting); });
    energy::flip(slots, sign);
  }

  bool cohesive() const { return !std::holds_alternative<NormalHertz>(normal); }
  /// jkr contacts live beyond r_i + r_j, to the pull-off distance.
  bool beyond_contact() const { return std::holds_alternative<NormalJKR>(normal); }
  bool conducts_heat() const { return !std::holds_alternative<HeatNone>(heat); }

  /// Extra reach beyond r_i + r_j of a contact of effective radius reff (jkr: delta_c).
  double pulloff_distance(double reff) const
  {
    double d = 0.0;
    dispatch(normal, [&](const auto &m) { d = m.pulloff_distance(reff, Estar); });
    return d;
  }

  /// Does the contact exist?  rsq: squared distance, radsum: r_i + r_j (wall: r_i and rsq the
  /// squared distance to the wall), touched: it existed at the last step.
  bool touching(double rsq, double radsum, double reff, bool touched) const
  {
    if (touched && beyond_contact()) {
      const double d = radsum + pulloff_distance(reff);
      return rsq < d * d;
    }
    return rsq < radsum * radsum;
  }

  /// Per-contact k_H, c0, tau of a contact with m* and R*.
  ContactCoeffs coeffs(double meff, double reff) const { return damping.coeffs(Estar, meff, reff); }

  /// The model of an unset type pair from its two types' models (native pair granular's
  /// mixing; E* and G* are the caller's).  Returns "" or the kind that differs ("rolling
  /// model", "damping law", ...).
  static std::string mix(const ContactModel &a, const ContactModel &b, ContactModel &m)
  {
    m = a;
    std::string what;
    if (!mix_alternatives(a.normal, b.normal, m.normal)) return "normal model";
    if (!DampingLaw::mix(a.damping, b.damping, m.damping, what)) return what;
    if (!mix_alternatives(a.tangential, b.tangential, m.tangential)) return "tangential model";
    if (!mix_alternatives(a.rolling, b.rolling, m.rolling)) return "rolling model";
    if (!mix_alternatives(a.twisting, b.twisting, m.twisting)) return "twisting model";
    if (!mix_alternatives(a.heat, b.heat, m.heat)) return "heat model";
    return "";
  }

  /// The restart records of the sub-models, in the order of composition.
  std::vector<Record> records() const
  {
    return {record_of(normal, "normal"), damping.record(), record_of(tangential, "tangential"),
            record_of(rolling, "rolling"), record_of(twisting, "twisting"), record_of(heat, "heat")};
  }
  /// The sub-models from their records (as records() wrote them); "" or an error.
  std::string from_records(const std::vector<Record> &r)
  {
    if (r.size() != 6) return "restart holds " + std::to_string(r.size()) + " sub-model records, expected 6";
    std::string err = from_record(normal, "normal", r[0]);
    if (err.empty()) err = damping.from_record(r[1]);
    if (err.empty()) err = from_record(tangential, "tangential", r[2]);
    if (err.empty()) err = from_record(rolling, "rolling", r[3]);
    if (err.empty()) err = from_record(twisting, "twisting", r[4]);
    if (err.empty()) err = from_record(heat, "heat", r[5]);
    return err;
  }

  /// When a contact ends (apart, or beyond pull-off), the elastic energy it still holds is lost,
  /// and so is the second half of its last forces' work (they acted over the step that parted
  /// it): adds both to diss[NDISS] (normal part: adhesion hysteresis, the pull-off jump;
  /// springs: sliding, rolling, twisting) and returns the total.  now: this step's velocities
  /// and dt (vr, omega_i, omega_j, reff, dt, wall; the rest unused), or nullptr where the caller
  /// has none (the last step's are used then).
  double release(const double *h, double *diss, const ContactGeometry *now = nullptr) const
  {
    return energy::release(slots, h, diss, now);
  }

  /// A stored contact h of a format-2 restart: its damping slot from the start time t0 to the
  /// relaxation g at t_now (DampingLaw::from_start_time); cc: its coefficients.
  void relaxation_from_start_time(double *h, const ContactCoeffs &cc, double t_now) const
  {
    if (slots.damping >= 0) DampingLaw::from_start_time(h + slots.damping, cc.tau, t_now);
  }

  /// THE contact step.  history: history_size() values of this contact (touch slot 0: a new
  /// contact, which is initialised here).  advance = false in a run's setup force call and in
  /// single() (on a copy): displacements are not incremented and no energy is dissipated (the
  /// Coulomb cap and the rescale still rewrite the tangential history, as native); the energy
  /// slots still take this evaluation's forces and elastic energies, where the first step's
  /// work starts (energy::count).
  void evaluate(const ContactGeometry &g, double *h, bool advance, ContactResult &res) const;

 private:
  HistorySlots slots;
};

VISCONTACT_ALWAYS_INLINE void ContactModel::evaluate(const ContactGeometry &g, double *__restrict h,
                                                     bool advance, ContactResult &__restrict res) const
{
  ContactState s;
  for (int k = 0; k < 3; k++) s.n[k] = g.n[k];
  s.delta = g.delta;
  s.reff = g.reff;
  s.dt = g.dt;
  s.t_now = g.t_now;
  s.wall = g.wall;
  s.advance = advance;
  s.energy = track_energy;
  s.Estar = Estar;
  s.Gstar = Gstar;

  // kinematics: v_n (< 0 approaching), slip velocity v_tr = v_t - (r_i w_i + r_j w_j) x n
  const double rj = g.wall ? 0.0 : g.r_j;
  double wr[3];
  for (int k = 0; k < 3; k++) wr[k] = g.r_i * g.omega_i[k] + rj * g.omega_j[k];
  s.vn = relative_tangential_velocity(g.vr, wr, s.n, s.vtr);
  detail::relative_rotation(g, s.relrot);

  // a new contact: fresh history and Jian's relaxation
  double *hd = slots.damping >= 0 ? h + slots.damping : nullptr;
  s.fresh = h[slots.touch] == 0.0;
  ContactCoeffs own;    // (the caller caches none: this contact's own, with its step factors)
  if (!g.coeffs) {
    own = coeffs(g.meff, g.reff);
    relaxation_step(own, g.dt);
  }
  s.cc = g.coeffs ? g.coeffs : &own;
  if (s.fresh) {
    for (int k = 0; k < slots.size; k++) h[k] = 0.0;
    h[slots.touch] = 1.0;
    damping.start(s, hd);
  }

  // normal, damping, critical force, tangential (and its torques), rolling, twisting, heat
  dispatch(normal, [&](const auto &m) VISCONTACT_INLINE_LAMBDA { m.calculate(s); });
  damping.calculate(s, hd);
  dispatch(normal, [&](const auto &m) VISCONTACT_INLINE_LAMBDA { m.critical_force(s); });
  dispatch(tangential, [&](const auto &m) VISCONTACT_INLINE_LAMBDA { m.calculate(s, h + slots.tangential); });
  double nxf[3];
  detail::cross3(s.n, s.ft, nxf);
  const double arms[2] = {g.wall ? g.r_i : g.r_i - 0.5 * s.delta, g.wall ? 0.0 : g.r_j - 0.5 * s.delta};
  for (int k = 0; k < 3; k++) {
    res.torque_i[k] = -arms[0] * nxf[k];
    res.torque_j[k] = g.wall ? 0.0 : -arms[1] * nxf[k];
  }
  dispatch(rolling, [&](const auto &m) VISCONTACT_INLINE_LAMBDA { m.calculate(s, h + slots.rolling, res); });
  dispatch(twisting, [&](const auto &m) VISCONTACT_INLINE_LAMBDA { m.calculate(s, h + slots.twisting, res); });
  dispatch(heat, [&](const auto &m) VISCONTACT_INLINE_LAMBDA { res.heat = m.flow(s, g); });

  res.a = s.a;
  res.fne = s.fne;
  res.fn = s.fn;
  res.fdamp = s.fn - s.fne;
  res.tau_twist = s.tau_twist;
  for (int k = 0; k < 3; k++) {
    res.force[k] = s.fn * s.n[k] + s.ft[k];
    res.ft[k] = s.ft[k];
    res.fr[k] = s.fr[k];
  }
  if (!track_energy) {
    for (int k = 0; k < NDISS; k++) res.dissipated[k] = 0.0;
    for (int k = 0; k < NELASTIC; k++) res.elastic[k] = 0.0;
    res.power = 0.0;
    return;
  }
  energy::count(slots, s, g, arms, h, res);
}

/// The keywords of one pair_coeff line or wall fix after the normal model: take() each, then
/// finish() once.
class ContactKeywords {
 public:
  /// If args[i] is one of `damping`, `end`, `tangential`, `rolling`, `twisting`, `heat`,
  /// consume it with its values into m, advance i and return true; otherwise return false and
  /// leave i.  err is set on a bad value.
  bool take(const Args &args, size_t &i, ContactModel &m, std::string &err)
  {
    if (damping.take(args, i, m.damping, err)) return true;
    const std::string &kw = args[i];
    if (kw == "tangential") {
      std::vector<std::string> forms = alternative_usages(&m.tangential);
      forms.erase(forms.begin());    // none
      return take_kind(args, i, m.tangential, seen_tangential, err,
                       "none or mindlin MU, or " + join_alternatives(forms), true);
    }
    if (kw == "rolling")
      return take_kind(args, i, m.rolling, seen_rolling, err,
                       join_alternatives(alternative_usages(&m.rolling)), false);
    if (kw == "twisting")
      return take_kind(args, i, m.twisting, seen_twisting, err,
                       join_alternatives(alternative_usages(&m.twisting)), false);
    if (kw == "heat")
      return take_kind(args, i, m.heat, seen_heat, err,
                       join_alternatives(alternative_usages(&m.heat)), false);
    return false;
  }

  /// Check that the keywords form one complete model; "" when they do.
  std::string finish(ContactModel &m)
  {
    std::string err = damping.check_given();
    if (!err.empty()) return err;
    if (!seen_tangential)
      return "missing tangential none | mindlin MU | " +
          join_alternatives(tail(alternative_usages(&m.tangential)), " | ", " | ") +
          " (one is required)";
    std::string normal_name;
    dispatch(m.normal, [&](const auto &x) { normal_name = std::decay_t<decltype(x)>::NAME; });
    err = damping.check_end(m.damping, m.cohesive(), normal_name);
    if (!err.empty()) return err;
    if (std::holds_alternative<TwistingMarshall>(m.twisting) && !has_spring(m.tangential))
      return "twisting marshall needs a tangential spring: linear_history or a mindlin model";
    return damping.finish(m.damping);
  }

 private:
  DampingKeywords damping;
  bool seen_tangential = false, seen_rolling = false, seen_twisting = false, seen_heat = false;

  static std::vector<std::string> tail(std::vector<std::string> v)
  {
    v.erase(v.begin());
    return v;
  }

  /// `KIND NAME values` at args[i] into v; allowed: the alternatives for the message.
  template <class V>
  static bool take_kind(const Args &args, size_t &i, V &v, bool &seen, std::string &err,
                        const std::string &allowed, bool got)
  {
    const std::string kind = args[i];
    if (seen) return (err = kind + " given twice"), true;
    seen = true;
    const std::string name = i + 1 < args.size() ? args[i + 1] : "";
    const size_t at = i + 1;
    i += 2;
    if (!parse_alternative(v, name, args, i, err))
      err = kind + " must be followed by " + allowed + (got ? "; got " + quoted(name) : "") +
          native_hint(args, at);
    return true;
  }
};

}    // namespace viscontact

#endif
