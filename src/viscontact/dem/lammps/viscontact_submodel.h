/* viscontact_submodel.h -- what every sub-model of the contact model shares: one contact's
   geometry (ContactGeometry), the values one evaluation passes from sub-model to sub-model
   (ContactState, LAMMPS GranularModel's locals), what it produces (ContactResult), the restart
   record, and the static dispatch over a sub-model kind's alternatives.

   A sub-model is one type (viscontact_normal.h, viscontact_damping.h, viscontact_tangential.h,
   viscontact_rolling.h, viscontact_twisting.h, viscontact_heat.h) with:
     NAME                      its keyword as users write it ("linear_history")
     std::string usage()       its values for messages ("KT XGAMMA MU")
     std::string parse(args, i)  its values at args[i] (past its name); advances i; "" or error
     static T mix(a, b)        the mixed sub-model of two types (geometric means, as native)
     NHIST, flip(sign)         its history values and their signs when i and j swap
     VERSION, coefficients(), from_coefficients(values)   its restart record
     calculate(state, h, ...)  its force or torque and elastic energy, in LAMMPS's order
   and each kind is a std::variant of its alternatives (the registration), visited with
   dispatch() (an index test per alternative, inlined: no virtual call per contact).

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_SUBMODEL_H
#define VISCONTACT_SUBMODEL_H

#include "viscontact_contact.h"
#include "viscontact_keywords.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

/// The contact step is inlined into the callers' loops (pair, wall), so that the geometry and
/// the result live in registers rather than in memory (measured: about 30 % of the pair's time).
#if defined(__GNUC__)
#define VISCONTACT_ALWAYS_INLINE inline __attribute__((always_inline))
/// The same for a lambda (after its parameter list): a sub-model's step called through
/// dispatch() is inlined too, so that the contact's state stays in registers (measured: an
/// out-of-line tangential step made the all-sub-models case about 20 % slower).
#define VISCONTACT_INLINE_LAMBDA __attribute__((always_inline))
#else
#define VISCONTACT_ALWAYS_INLINE inline
#define VISCONTACT_INLINE_LAMBDA
#endif
/// A function whose loads of freshly stored doubles GCC's SLP vectorizer would pair into one
/// 16-byte load (not forwardable from two 8-byte stores: a stall of the store's retirement).
#if defined(__GNUC__) && !defined(__clang__)
#define VISCONTACT_NO_SLP __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define VISCONTACT_NO_SLP
#endif

namespace viscontact {

constexpr double PI = 3.14159265358979323846;

/// Dissipation mechanisms, in the order of every energy column.
enum Dissipation {
  DISS_NORMAL_DAMPING = 0, DISS_TANGENTIAL_DAMPING, DISS_SLIDING, DISS_ROLLING, DISS_TWISTING,
  DISS_ADHESION, NDISS
};
/// Elastic energy parts, in the order of every energy column.
enum Elastic { ELASTIC_NORMAL = 0, ELASTIC_TANGENTIAL, ELASTIC_ROLLING, ELASTIC_TWISTING, NELASTIC };

/// Geometry and kinematics of one contact.  Pair: n = (x_i - x_j)/r, r_j > 0.  Wall: n from the
/// wall to the sphere, wall = true (lever arm r_i, no torque on j, omega_j = 0).
struct ContactGeometry {
  double n[3];                  ///< unit normal, from j (or the wall) to i
  double delta;                 ///< overlap r_i + r_j - r (wall: r_i - distance) [length]
  double r_i, r_j;              ///< radii (wall: r_j unused)
  double reff, meff;            ///< R*, m*
  double vr[3];                 ///< v_i - v_j (wall: v_i - v_wall)
  double omega_i[3], omega_j[3];
  double dt, t_now;             ///< time step, time now
  double T_i = 0.0, T_j = 0.0;  ///< temperatures (heat area)
  bool wall = false;
  const ContactCoeffs *coeffs = nullptr;    ///< per-contact k_H, c0, tau if the caller caches them
};

/// Everything one evaluation produces.
struct ContactResult {
  double force[3];       ///< total contact force on i (j gets its negative)
  double torque_i[3], torque_j[3];
  double heat;           ///< heat flow into i (j gets its negative)
  double fn, fne, fdamp; ///< F_n (after the clamp), F_ne (elastic), F_n - F_ne
  double ft[3], fr[3];   ///< tangential force on i, rolling pseudo-force
  double tau_twist;      ///< twisting torque magnitude along n on i
  double a;              ///< contact radius
  double dissipated[NDISS];   ///< energy dissipated over this step (dt), per mechanism; added to
                              ///< the contact's history only when the history advances
  double elastic[NELASTIC];   ///< elastic energy stored now
  double power;               ///< total dissipated power of the step (sum dissipated / dt)

  /// The mechanics times f (a special_bonds factor, 0 < f < 1, as pair granular applies it):
  /// forces, torques and so the work, dissipated and elastic energies.  The heat flow and the
  /// contact radius stay (pair granular conducts heat through a bonded contact unscaled).
  void scale(double f)
  {
    for (int k = 0; k < 3; k++) {
      force[k] *= f;
      torque_i[k] *= f;
      torque_j[k] *= f;
      ft[k] *= f;
      fr[k] *= f;
    }
    fn *= f;
    fne *= f;
    fdamp *= f;
    tau_twist *= f;
    for (double &d : dissipated) d *= f;
    for (double &e : elastic) e *= f;
    power *= f;
  }
};

/// What one evaluation passes from sub-model to sub-model (each writes its part, in LAMMPS's
/// order: normal, damping, critical force, tangential, rolling, twisting, heat).
struct ContactState {
  double n[3], delta, reff, dt, t_now;
  bool wall;                 ///< a wall contact (no j)
  double vn;                 ///< v_r . n (< 0 approaching); the overlap rate is -vn
  double vtr[3];             ///< slip velocity v_t - (r_i w_i + r_j w_j) x n
  double relrot[3];          ///< w_i - w_j (a wall: w_i)
  bool fresh, advance, energy;
  double Estar, Gstar;       ///< the contact's effective moduli
  /// k_H, c0, tau of this contact, with the relaxation's step factors for dt (a pointer, not a
  /// copy: no per-contact copy of the caller's cached coefficients)
  const ContactCoeffs *cc;
  // normal model
  double a = 0.0, fne = 0.0, fpo = 0.0, delta_a = 0.0, U = 0.0;
  bool cohesive = false;
  // damping
  double eta_n = 0.0, fn = 0.0;
  double F0 = 0.0;           ///< critical force of the Coulomb limits
  // tangential (k_t, eta_t, mu_t also serve twisting marshall)
  double k_t = 0.0, eta_t = 0.0, mu_t = 0.0;
  double ft[3] = {0.0, 0.0, 0.0}, fdamp_t[3] = {0.0, 0.0, 0.0}, el_t = 0.0;
  // rolling, twisting
  double fr[3] = {0.0, 0.0, 0.0}, el_r = 0.0;
  double tau_twist = 0.0, el_w = 0.0;
};

/// The sub-models' vector helpers are always inlined too: called from two sub-models, GCC left
/// rotate_rescale out of line, and the tangential and rolling displacements then went through
/// memory and a call each contact and step (measured: 1,090 of the 1,206 instructions per
/// particle-step the all-sub-models case had lost with the split into sub-model types).
namespace detail {
VISCONTACT_ALWAYS_INLINE double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
VISCONTACT_ALWAYS_INLINE void cross3(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
/// Power of a tangential force F on i (-F on j) with its torques -d_i (n x F) on i and
/// -d_j (n x F) on j: F . v_r - (n x F) . (d_i w_i + d_j w_j) (a wall: no j).
VISCONTACT_ALWAYS_INLINE double tangential_power(const double *F, const double *n, const double *d,
                               const ContactGeometry &g)
{
  double nxF[3], w[3];
  cross3(n, F, nxF);
  for (int k = 0; k < 3; k++) w[k] = d[0] * g.omega_i[k] + (g.wall ? 0.0 : d[1] * g.omega_j[k]);
  return dot3(F, g.vr) - dot3(nxF, w);
}

/// w_i - w_j (a wall: w_i).
VISCONTACT_ALWAYS_INLINE void relative_rotation(const ContactGeometry &g, double *rel)
{
  for (int k = 0; k < 3; k++) rel[k] = g.wall ? g.omega_i[k] : g.omega_i[k] - g.omega_j[k];
}

/// Project v onto the plane normal to n and restore its length.
VISCONTACT_ALWAYS_INLINE void rotate_rescale(double *v, const double *n)
{
  const double len = std::sqrt(dot3(v, v));
  const double vn = dot3(v, n);
  for (int k = 0; k < 3; k++) v[k] -= vn * n[k];
  const double plen = std::sqrt(dot3(v, v));
  const double s = plen > 0.0 ? len / plen : 0.0;
  for (int k = 0; k < 3; k++) v[k] *= s;
}

/// The geometric mean, native pair granular's mixing of a coefficient.
inline double geo(double x, double y) { return std::sqrt(x * y); }
}    // namespace detail

/* ---- restart records: one per sub-model, by name, with its coefficients and version ------ */

/// One sub-model's record: "KIND NAME" (e.g. "tangential mindlin"), its record version and
/// its coefficients.
struct Record {
  std::string name;
  int version = 0;
  std::vector<double> values;
};

/// Records as bytes: [int name length][name][int version][int count][count doubles] each.
class RecordWriter {
 public:
  void add(const Record &r)
  {
    put_int(static_cast<int>(r.name.size()));
    bytes.insert(bytes.end(), r.name.begin(), r.name.end());
    put_int(r.version);
    put_int(static_cast<int>(r.values.size()));
    const char *p = reinterpret_cast<const char *>(r.values.data());
    bytes.insert(bytes.end(), p, p + r.values.size() * sizeof(double));
  }
  std::vector<char> bytes;

 private:
  void put_int(int v)
  {
    const char *p = reinterpret_cast<const char *>(&v);
    bytes.insert(bytes.end(), p, p + sizeof v);
  }
};

class RecordReader {
 public:
  RecordReader(const char *data, size_t size) : p(data), end(data + size) {}
  /// The next record; false when the bytes end or are malformed.
  bool next(Record &r)
  {
    int len = 0, count = 0;
    if (!get_int(len) || len < 0 || (size_t) len > (size_t) (end - p)) return false;
    r.name.assign(p, p + len);
    p += len;
    if (!get_int(r.version) || !get_int(count) || count < 0 ||
        (size_t) count * sizeof(double) > (size_t) (end - p))
      return false;
    r.values.resize(count);
    if (count) std::memcpy(r.values.data(), p, count * sizeof(double));
    p += count * sizeof(double);
    return true;
  }

 private:
  const char *p, *end;
  bool get_int(int &v)
  {
    if ((size_t) (end - p) < sizeof v) return false;
    std::memcpy(&v, p, sizeof v);
    p += sizeof v;
    return true;
  }
};

/* ---- static dispatch over a kind's alternatives ------------------------------------------ */

template <class T, class First, class... Rest> constexpr size_t index_of()
{
  if constexpr (std::is_same_v<T, First>) return 0;
  else return 1 + index_of<T, Rest...>();
}

/// f(the alternative v holds): one index test per alternative, inlined (no virtual call).
template <class F, class... Ts>
VISCONTACT_ALWAYS_INLINE void dispatch(const std::variant<Ts...> &v, F &&f)
{
  (void) ((v.index() == index_of<Ts, Ts...>() ? (f(*std::get_if<Ts>(&v)), true) : false) || ...);
}

/// Tag of an alternative users do not name (a kind's default `none` where no keyword selects
/// it: rolling, twisting, heat).
struct Absent {};
template <class T> constexpr bool selectable = !std::is_base_of_v<Absent, T>;

/// The NAMEs of a kind's alternatives, in their order.
template <class... Ts> std::vector<std::string> alternative_names(const std::variant<Ts...> *)
{
  return {std::string(Ts::NAME)...};
}

/// "NAME usage" of each alternative a user can name (NAME alone when it takes no values),
/// for messages.
template <class... Ts> std::vector<std::string> alternative_usages(const std::variant<Ts...> *)
{
  std::vector<std::string> out;
  auto one = [&out](bool named, const std::string &name, const std::string &usage) {
    if (named) out.push_back(usage.empty() ? name : name + " " + usage);
  };
  (one(selectable<Ts>, Ts::NAME, Ts::usage()), ...);
  return out;
}

/// Make v the alternative called `name` and parse its values at args[i] (past the name);
/// false when no alternative has that name.
template <class... Ts>
bool parse_alternative(std::variant<Ts...> &v, const std::string &name, const Args &args,
                       size_t &i, std::string &err)
{
  return ((selectable<Ts> && name == Ts::NAME ? (err = v.template emplace<Ts>().parse(args, i), true)
                                               : false) || ...);
}

/// The mixed alternative of two types' sub-models of one kind; false when the kinds differ.
template <class... Ts>
bool mix_alternatives(const std::variant<Ts...> &a, const std::variant<Ts...> &b,
                      std::variant<Ts...> &out)
{
  if (a.index() != b.index()) return false;
  dispatch(a, [&](const auto &x) {
    using T = std::decay_t<decltype(x)>;
    out = T::mix(x, *std::get_if<T>(&b));
  });
  return true;
}

/// The record of the alternative v holds, named "kind NAME".
template <class... Ts> Record record_of(const std::variant<Ts...> &v, const std::string &kind)
{
  Record r;
  dispatch(v, [&](const auto &x) {
    using T = std::decay_t<decltype(x)>;
    r.name = kind + " " + T::NAME;
    r.version = T::VERSION;
    r.values = x.coefficients();
  });
  return r;
}

/// v from its record (as record_of wrote it); "" or an error naming the record.
template <class... Ts>
std::string from_record(std::variant<Ts...> &v, const std::string &kind, const Record &r)
{
  std::string err = "restart record " + quoted(r.name) + " is not a " + kind + " model";
  auto try_one = [&](auto *tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    if (r.name != kind + " " + T::NAME) return false;
    if (r.version < 1 || r.version > T::VERSION)
      err = "restart record " + r.name + " has version " + std::to_string(r.version) +
          "; this viscontact reads versions 1 to " + std::to_string(T::VERSION);
    else
      err = v.template emplace<T>().from_coefficients(r.values);
    return true;
  };
  (void) (try_one(static_cast<Ts *>(nullptr)) || ...);
  return err;
}

/// "" when `values` has n entries, else the message for a record of that name.
inline std::string check_count(const char *name, const std::vector<double> &values, size_t n)
{
  if (values.size() == n) return "";
  return std::string("restart record of ") + name + " has " + std::to_string(values.size()) +
      " values, expected " + std::to_string(n);
}

/// A sub-model without values, history or force (the `none` of a kind).
template <class Derived> struct NoValues {
  static constexpr int VERSION = 1;
  int history_size() const { return 0; }
  static std::string usage() { return ""; }
  std::string parse(const Args &, size_t &) { return ""; }
  static Derived mix(const Derived &a, const Derived &) { return a; }
  static void flip(double *) {}
  std::vector<double> coefficients() const { return {}; }
  std::string from_coefficients(const std::vector<double> &v)
  {
    return check_count(Derived::NAME, v, 0);
  }
};

}    // namespace viscontact

#endif
