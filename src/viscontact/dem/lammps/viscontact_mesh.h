/* The geometry of a triangle-mesh wall (fix viscontact/wall ... mesh FILE): an STL reader, the
   mesh's checks and connectivity, a bin grid of triangles, the closest point on a triangle and
   the rule that turns the triangles a sphere touches into contacts.  No LAMMPS in here: the fix
   (fix_wall_viscontact_mesh.cpp) moves the sphere into the mesh's frame and back.

   The contact rule (docs/fix_viscontact_mesh.md):
   - every triangle within reach s of the sphere centre x gives its closest point q_t (on its
     face, one of its edges or one of its vertices; Ericson, Real-Time Collision Detection,
     2005, section 5.1.5);
   - a face point is a contact;
   - an edge or vertex point is a contact only if every triangle sharing that edge or vertex
     has its closest point there too, i.e. x lies in the feature's Voronoi region of the local
     mesh.  That is the case at a convex edge or vertex (one contact, from the edge or vertex,
     that turns continuously into the neighbouring faces' contacts) and at an open mesh's rim;
     it is never the case at a concave crease (each face there is its own contact, as region
     walls do with their faces) nor, but on a set of measure zero, inside a flat patch (where
     the face under the sphere gives the contact);
   - contacts whose points coincide (to 1e-9 s) are one contact: a sphere exactly above a
     shared edge or vertex of a flat patch touches it once, with the face normal where a face
     gave it;
   - a shallow concave crease (the facets of a curved wall seen from inside): contacts on
     triangles sharing a vertex whose normals differ by less than the crease angle (default
     30 degrees) are one contact, the deepest (two full face contacts there would double the
     force of a sphere sitting on the crease; with the deepest only, the force's size is
     continuous across it and its direction turns by the facets' angle).
   The globally closest point of the mesh always passes the test (each triangle through it has
   its closest point there), so a sphere within reach of the mesh always has a contact.

   Faces are flat (curvature radius 0: R* = r); the normal points from the closest point to the
   sphere centre, so a mesh has two sides and may be open (a blade) or closed (a box; a wall
   thinner than a sphere's radius should then be one open sheet, or the far side touches too).

   This file is part of viscontact.  Compiled into a LAMMPS plugin it links GPL-2 LAMMPS. */
#ifndef VISCONTACT_MESH_H
#define VISCONTACT_MESH_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace viscontact {
namespace mesh {

using Vec = std::array<double, 3>;

inline Vec sub(const Vec &a, const Vec &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec &a, const Vec &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec cross(const Vec &a, const Vec &b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec &a) { return std::sqrt(dot(a, a)); }

/// Where the closest point of a triangle lies: vertex k (0..2), edge k from vertex k to
/// vertex k+1 (EDGE + k), or the face.
enum Feature { VERTEX = 0, EDGE = 3, FACE = 6 };

/// The closest point q of triangle (a, b, c) to p and its feature (Ericson 2005, 5.1.5: the
/// Voronoi regions of the vertices, then of the edges, else the face).
inline int closest_point(const Vec &p, const Vec &a, const Vec &b, const Vec &c, Vec &q)
{
  const Vec ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) { q = a; return VERTEX + 0; }
  const Vec bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) { q = b; return VERTEX + 1; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    q = {a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]};
    return EDGE + 0;
  }
  const Vec cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) { q = c; return VERTEX + 2; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    q = {a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]};
    return EDGE + 2;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    q = {b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])};
    return EDGE + 1;
  }
  return FACE;    // q is set by the caller from the face normal (exact for flat patches)
}

/// Rotation matrix of angle (radians) about the unit axis u (right-hand rule).
inline std::array<Vec, 3> rotation(const Vec &u, double angle)
{
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  return {Vec{t * u[0] * u[0] + c, t * u[0] * u[1] - s * u[2], t * u[0] * u[2] + s * u[1]},
          Vec{t * u[0] * u[1] + s * u[2], t * u[1] * u[1] + c, t * u[1] * u[2] - s * u[0]},
          Vec{t * u[0] * u[2] - s * u[1], t * u[1] * u[2] + s * u[0], t * u[2] * u[2] + c}};
}

/// The placement applied to the file's coordinates on load: x -> R (scale x) + offset, R the
/// rotation by `angle` degrees about `axis` (none for angle 0).
struct Placement {
  double scale = 1.0;
  Vec axis{0.0, 0.0, 1.0};
  double angle = 0.0;    // degrees
  Vec offset{0.0, 0.0, 0.0};
};

/// One contact of a sphere with the mesh (mesh frame).
struct Hit {
  int tri;        ///< the triangle that gave it (the key of its history)
  int feature;    ///< VERTEX + k, EDGE + k or FACE of that triangle
  double dist;    ///< distance from the closest point to the sphere centre
  Vec n;          ///< unit normal from the closest point to the centre
  Vec q;          ///< the closest point
};

class TriangleMesh {
 public:
  /// Reads an STL file (binary or ASCII), places it and checks it.  Returns "" or the error.
  std::string load(const std::string &path, const Placement &place)
  {
    std::string err = read_stl(path);
    if (!err.empty()) return err;
    place_vertices(place);
    return build();
  }

  /// Builds from triangles given directly (three corners each), placed and checked.
  std::string set(const std::vector<std::array<Vec, 3>> &corners, const Placement &place)
  {
    raw = corners;
    place_vertices(place);
    return build();
  }

  int ntri() const { return static_cast<int>(tv.size()); }
  int nvert() const { return static_cast<int>(verts.size()); }
  const Vec &vertex(int v) const { return verts[v]; }
  const std::array<int, 3> &corners(int t) const { return tv[t]; }
  int max_valence() const { return maxval; }
  const Vec &lo() const { return bblo; }
  const Vec &hi() const { return bbhi; }

  /// Do triangles a and b share a vertex (or are they the same)?
  bool adjacent(int a, int b) const
  {
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        if (tv[a][i] == tv[b][j]) return true;
    return false;
  }

  /// The contacts of a sphere centred at x (mesh frame) with every triangle closer than s,
  /// by the rule at the top of this file.
  void contacts(const Vec &x, double s, std::vector<Hit> &out) const
  {
    out.clear();
    cand.clear();
    if (++query == 0) {    // wrapped: clear the marks
      std::fill(mark.begin(), mark.end(), 0u);
      query = 1;
    }
    int ilo[3], ihi[3];
    for (int d = 0; d < 3; d++) {
      if (x[d] + s < bblo[d] || x[d] - s > bbhi[d]) return;
      ilo[d] = cell_index(d, x[d] - s);
      ihi[d] = cell_index(d, x[d] + s);
    }
    for (int i = ilo[0]; i <= ihi[0]; i++)
      for (int j = ilo[1]; j <= ihi[1]; j++)
        for (int k = ilo[2]; k <= ihi[2]; k++) {
          const int c = (i * dims[1] + j) * dims[2] + k;
          for (int m = cstart[c]; m < cstart[c + 1]; m++) {
            // the distance to the triangle's plane bounds the distance to the triangle: most
            // entries end here, so first, from the entry's own copy of a corner and the normal
            // (no lookups through the triangle)
            const Entry &e = ctris[m];
            if (std::fabs(dot(sub(x, e.a), e.n)) >= s) continue;
            const int t = e.t;
            if (mark[t] == query) continue;
            mark[t] = query;
            const Hit h = closest(t, x);
            if (h.dist < s) cand.push_back(h);
          }
        }
    // in triangle order, whichever cells found them: the forces' summation order is the
    // mesh's, not the grid's
    if (cand.size() > 1)
      std::sort(cand.begin(), cand.end(), [](const Hit &a, const Hit &b) { return a.tri < b.tri; });
    const double eps = 1e-9 * s;
    for (const Hit &h : cand) {
      if (h.feature != FACE && !in_voronoi(h, x, eps)) continue;
      bool dup = false;
      for (Hit &o : out)
        if (norm(sub(o.q, h.q)) <= eps) {    // one contact: a face's normal wins
          if (o.feature != FACE && h.feature == FACE) o = h;
          dup = true;
          break;
        }
      if (!dup) out.push_back(h);
    }
    // a shallow concave crease (a curved wall's facets): of the contacts on triangles sharing
    // a vertex whose normals differ by less than the crease angle, the deepest acts alone
    if (out.size() < 2 || crease_cos > 1.0) return;
    for (size_t i = 0; i < out.size(); i++)
      for (size_t j = i + 1; j < out.size();) {
        if (dot(out[i].n, out[j].n) > crease_cos && adjacent(out[i].tri, out[j].tri)) {
          if (out[j].dist < out[i].dist) out[i] = out[j];
          out.erase(out.begin() + static_cast<long>(j));
          j = i + 1;
        } else {
          j++;
        }
      }
  }

  /// Concave creases whose contact normals differ by less than `degrees` give one contact
  /// (the deepest); 0: every face its own contact.
  void set_crease(double degrees)
  {
    crease_cos = degrees > 0.0 ? std::cos(degrees * M_PI / 180.0) : 2.0;
  }

  /// The closest point of triangle t to x, its feature, distance and normal (to x).
  Hit closest(int t, const Vec &x) const
  {
    Hit h;
    h.tri = t;
    const Vec &a = verts[tv[t][0]], &b = verts[tv[t][1]], &c = verts[tv[t][2]];
    h.feature = closest_point(x, a, b, c, h.q);
    bool along_normal = h.feature == FACE;
    if (!along_normal) {
      // an edge or vertex point straight below x (a flat patch's edge, the border of the
      // face's region): the face's own distance and normal, exact and continuous there
      const Vec d = sub(x, h.q);
      const Vec cr = cross(d, tn[t]);
      along_normal = dot(cr, cr) <= 1e-24 * dot(d, d);
    }
    if (along_normal) {
      // the distance along the face normal: exact for a patch in a coordinate plane
      const Vec &n = tn[t];
      const double sd = dot(sub(x, a), n);
      const double sg = sd < 0.0 ? -1.0 : 1.0;
      h.dist = std::fabs(sd);
      h.n = {sg * n[0], sg * n[1], sg * n[2]};
      h.q = {x[0] - sd * n[0], x[1] - sd * n[1], x[2] - sd * n[2]};
    } else {
      const Vec d = sub(x, h.q);
      h.dist = norm(d);
      const double inv = h.dist > 0.0 ? 1.0 / h.dist : 0.0;
      h.n = {d[0] * inv, d[1] * inv, d[2] * inv};
    }
    return h;
  }

 private:
  std::vector<std::array<Vec, 3>> raw;    // the file's triangles, then placed
  std::vector<Vec> verts;                 // welded vertices
  std::vector<std::array<int, 3>> tv;     // triangle -> vertices
  std::vector<Vec> tn;                    // unit face normals (right-hand order)
  std::vector<int> vstart, vtris;         // vertex -> triangles (CSR)
  std::vector<std::array<int, 2>> etris;  // edge -> its one or two triangles (-1: none)
  std::vector<std::array<int, 3>> te;     // triangle -> edge k (vertex k to k+1)
  int maxval = 0;
  double crease_cos = std::cos(30.0 * M_PI / 180.0);
  Vec bblo{}, bbhi{};
  // the bin grid
  double h = 1.0;
  int dims[3] = {1, 1, 1};
  /// A bin's entry: the triangle, a copy of its first corner and its unit normal (its plane).
  struct Entry {
    Vec a, n;
    int t;
  };
  std::vector<int> cstart;
  std::vector<Entry> ctris;
  mutable std::vector<uint32_t> mark;
  mutable uint32_t query = 0;
  mutable std::vector<Hit> cand;

  int cell_index(int d, double v) const
  {
    const int i = static_cast<int>(std::floor((v - bblo[d]) / h));
    return std::min(std::max(i, 0), dims[d] - 1);
  }

  /// Does triangle t's plane cross cell (i, j, k) (its centre within half a cell's extent
  /// along the normal, with a margin for rounding)?
  bool plane_crosses(int t, int i, int j, int k) const
  {
    const Vec &n = tn[t], &a = verts[tv[t][0]];
    const double reach = 0.5 * h * (std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]));
    const Vec centre{bblo[0] + (i + 0.5) * h, bblo[1] + (j + 0.5) * h, bblo[2] + (k + 0.5) * h};
    return std::fabs(dot(sub(centre, a), n)) <= reach * (1.0 + 1e-9) + 1e-12 * h;
  }

  /// Does triangle t overlap cell (i, j, k), grown by a margin for rounding?  The separating
  /// axis test (Akenine-Moeller 2001, "Fast 3D triangle-box overlap testing") on the edges'
  /// cross products with the cell's axes; the caller has tested the plane (plane_crosses) and
  /// the cell lies in the triangle's bounding box.
  bool overlaps(int t, int i, int j, int k) const
  {
    const double e = 0.5 * h * (1.0 + 1e-9) + 1e-12 * h;
    const Vec centre{bblo[0] + (i + 0.5) * h, bblo[1] + (j + 0.5) * h, bblo[2] + (k + 0.5) * h};
    const Vec v[3] = {sub(verts[tv[t][0]], centre), sub(verts[tv[t][1]], centre),
                      sub(verts[tv[t][2]], centre)};
    for (int m = 0; m < 3; m++) {
      const Vec f = sub(v[(m + 1) % 3], v[m]);
      for (int d = 0; d < 3; d++) {
        Vec axis{0.0, 0.0, 0.0};    // unit axis d cross f
        axis[(d + 1) % 3] = -f[(d + 2) % 3];
        axis[(d + 2) % 3] = f[(d + 1) % 3];
        const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
        const double r = e * (std::fabs(axis[0]) + std::fabs(axis[1]) + std::fabs(axis[2]));
        const double slack = 1e-9 * (std::fabs(p0) + std::fabs(p1) + std::fabs(p2) + r);
        if (std::min({p0, p1, p2}) > r + slack || std::max({p0, p1, p2}) < -r - slack)
          return false;
      }
    }
    return true;
  }

  /// Is an edge or vertex point h of the Voronoi region of its feature: does every triangle
  /// sharing the feature have its closest point there?
  bool in_voronoi(const Hit &hit, const Vec &x, double eps) const
  {
    const int t = hit.tri;
    if (hit.feature >= EDGE) {
      for (int u : etris[te[t][hit.feature - EDGE]])
        if (u >= 0 && u != t && norm(sub(closest(u, x).q, hit.q)) > eps) return false;
      return true;
    }
    const int v = tv[t][hit.feature - VERTEX];
    for (int m = vstart[v]; m < vstart[v + 1]; m++)
      if (vtris[m] != t && norm(sub(closest(vtris[m], x).q, hit.q)) > eps) return false;
    return true;
  }

  static std::string fmt(const Vec &v)
  {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", v[0], v[1], v[2]);
    return buf;
  }

  std::string read_stl(const std::string &path)
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "cannot open mesh file " + path;
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    raw.clear();
    if (data.size() >= 84) {    // binary: an 80-byte header, a count, 50 bytes per triangle
      uint32_t n;
      std::memcpy(&n, data.data() + 80, 4);
      if (data.size() == 84 + 50 * static_cast<uint64_t>(n)) {
        for (uint32_t t = 0; t < n; t++) {
          const char *rec = data.data() + 84 + 50 * static_cast<size_t>(t) + 12;
          std::array<Vec, 3> tri;
          for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++) {
              float f;
              std::memcpy(&f, rec + 4 * (3 * k + d), 4);
              tri[k][d] = f;
            }
          raw.push_back(tri);
        }
        return raw.empty() ? "mesh file " + path + " holds no triangles" : "";
      }
    }
    // ASCII: solid ... facet normal ... outer loop vertex x y z (3) endloop endfacet ...
    std::istringstream ss(data);
    std::string word;
    ss >> word;
    if (word != "solid")
      return "mesh file " + path + " is neither a binary STL (84 + 50 n bytes) nor an ASCII "
             "STL (starting with 'solid')";
    std::vector<Vec> loop;
    while (ss >> word) {
      if (word == "vertex") {
        Vec v;
        std::string tok[3];
        ss >> tok[0] >> tok[1] >> tok[2];
        for (int d = 0; d < 3; d++) {
          char *end = nullptr;
          v[d] = std::strtod(tok[d].c_str(), &end);
          if (tok[d].empty() || *end != '\0')
            return "mesh file " + path + ": facet " + std::to_string(raw.size() + 1) +
                   " has a vertex coordinate that is not a number: '" + tok[d] + "'";
        }
        loop.push_back(v);
      } else if (word == "endloop") {
        if (loop.size() != 3)
          return "mesh file " + path + ": facet " + std::to_string(raw.size() + 1) + " has " +
                 std::to_string(loop.size()) + " vertices; STL facets are triangles";
        raw.push_back({loop[0], loop[1], loop[2]});
        loop.clear();
      }
    }
    return raw.empty() ? "mesh file " + path + " holds no triangles" : "";
  }

  void place_vertices(const Placement &p)
  {
    const bool turn = p.angle != 0.0;
    std::array<Vec, 3> rot{};
    if (turn) {
      const double len = norm(p.axis);
      rot = rotation({p.axis[0] / len, p.axis[1] / len, p.axis[2] / len},
                     p.angle * M_PI / 180.0);
    }
    for (auto &tri : raw)
      for (Vec &v : tri) {
        Vec s = {p.scale * v[0], p.scale * v[1], p.scale * v[2]};
        if (turn) s = {dot(rot[0], s), dot(rot[1], s), dot(rot[2], s)};
        for (int d = 0; d < 3; d++) v[d] = s[d] + p.offset[d];
      }
  }

  /// Welds equal corners into vertices, checks the triangles (finite, not degenerate, no
  /// edge of more than two triangles, no triangle twice), links edges and vertices to their
  /// triangles and bins the triangles.
  std::string build()
  {
    verts.clear();
    tv.clear();
    tn.clear();
    std::map<Vec, int> index;
    for (size_t t = 0; t < raw.size(); t++) {
      std::array<int, 3> ids;
      for (int k = 0; k < 3; k++) {
        const Vec &v = raw[t][k];
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
          return "triangle " + std::to_string(t + 1) + " has a corner that is not finite";
        auto it = index.find(v);
        if (it == index.end()) {
          it = index.emplace(v, static_cast<int>(verts.size())).first;
          verts.push_back(v);
        }
        ids[k] = it->second;
      }
      const Vec e0 = sub(raw[t][1], raw[t][0]), e1 = sub(raw[t][2], raw[t][1]),
                e2 = sub(raw[t][0], raw[t][2]);
      const double lmax = std::max({norm(e0), norm(e1), norm(e2)});
      const Vec c = cross(e0, sub(raw[t][2], raw[t][0]));
      if (!(norm(c) > 1e-10 * lmax * lmax))
        return "triangle " + std::to_string(t + 1) + " " + fmt(raw[t][0]) + " " +
               fmt(raw[t][1]) + " " + fmt(raw[t][2]) +
               " is degenerate (zero area or a needle): remove it or repair the mesh";
      const double len = norm(c);
      tv.push_back(ids);
      tn.push_back({c[0] / len, c[1] / len, c[2] / len});
    }
    // edges: each shared by at most two triangles; no triangle twice
    std::map<std::pair<int, int>, int> edge;
    std::map<std::array<int, 3>, int> seen;
    etris.clear();
    te.assign(tv.size(), {-1, -1, -1});
    for (size_t t = 0; t < tv.size(); t++) {
      std::array<int, 3> key = tv[t];
      std::sort(key.begin(), key.end());
      if (!seen.emplace(key, static_cast<int>(t)).second)
        return "triangles " + std::to_string(seen[key] + 1) + " and " + std::to_string(t + 1) +
               " have the same corners: remove the duplicate";
      for (int k = 0; k < 3; k++) {
        const int a = tv[t][k], b = tv[t][(k + 1) % 3];
        const auto e = std::make_pair(std::min(a, b), std::max(a, b));
        auto it = edge.find(e);
        if (it == edge.end()) {
          it = edge.emplace(e, static_cast<int>(etris.size())).first;
          etris.push_back({static_cast<int>(t), -1});
        } else if (etris[it->second][1] < 0) {
          etris[it->second][1] = static_cast<int>(t);
        } else {
          return "the mesh is not manifold: the edge " + fmt(verts[a]) + " - " + fmt(verts[b]) +
                 " belongs to more than two triangles (" +
                 std::to_string(etris[it->second][0] + 1) + ", " +
                 std::to_string(etris[it->second][1] + 1) + ", " + std::to_string(t + 1) +
                 "): split the mesh into separate walls";
        }
        te[t][k] = it->second;
      }
    }
    // vertex -> triangles
    vstart.assign(verts.size() + 1, 0);
    for (const auto &ids : tv)
      for (int v : ids) vstart[v + 1]++;
    for (size_t v = 0; v < verts.size(); v++) vstart[v + 1] += vstart[v];
    vtris.assign(vstart.back(), 0);
    std::vector<int> fill(vstart.begin(), vstart.end() - 1);
    maxval = 0;
    for (size_t t = 0; t < tv.size(); t++)
      for (int v : tv[t]) vtris[fill[v]++] = static_cast<int>(t);
    for (size_t v = 0; v < verts.size(); v++) maxval = std::max(maxval, vstart[v + 1] - vstart[v]);
    bin();
    return "";
  }

  /// A uniform grid over the bounding box, cells about the median triangle size (capped at
  /// the root of the mean triangle area; at most about 2e6 cells); each triangle listed
  /// in every cell of its bounding box that its plane crosses.
  void bin()
  {
    bblo = bbhi = verts[0];
    for (const Vec &v : verts)
      for (int d = 0; d < 3; d++) {
        bblo[d] = std::min(bblo[d], v[d]);
        bbhi[d] = std::max(bbhi[d], v[d]);
      }
    std::vector<double> size;
    for (const auto &ids : tv) {
      double ext = 0.0;
      for (int d = 0; d < 3; d++) {
        double a = verts[ids[0]][d], b = a;
        for (int v : ids) {
          a = std::min(a, verts[v][d]);
          b = std::max(b, verts[v][d]);
        }
        ext = std::max(ext, b - a);
      }
      size.push_back(ext);
    }
    std::nth_element(size.begin(), size.begin() + size.size() / 2, size.end());
    // the median extent, but no more than the root of the mean area: long thin
    // triangles (a cone's, a tube's) then span several cells instead of each cell holding all
    double area = 0.0;
    for (const auto &ids : tv)
      area += 0.5 * norm(cross(sub(verts[ids[1]], verts[ids[0]]), sub(verts[ids[2]], verts[ids[0]])));
    h = std::min(size[size.size() / 2], std::sqrt(area / static_cast<double>(tv.size())));
    for (;;) {
      double ncell = 1.0;
      for (int d = 0; d < 3; d++) {
        dims[d] = std::max(1, static_cast<int>(std::ceil((bbhi[d] - bblo[d]) / h)));
        ncell *= dims[d];
      }
      if (ncell <= 2e6) break;
      h *= 1.5;
    }
    const int ncell = dims[0] * dims[1] * dims[2];
    std::vector<std::array<int, 6>> span(tv.size());
    cstart.assign(ncell + 1, 0);
    for (int pass = 0; pass < 2; pass++) {
      std::vector<int> fill(cstart.begin(), cstart.end() - 1);
      for (size_t t = 0; t < tv.size(); t++) {
        auto &r = span[t];
        if (pass == 0)
          for (int d = 0; d < 3; d++) {
            double a = verts[tv[t][0]][d], b = a;
            for (int v : tv[t]) {
              a = std::min(a, verts[v][d]);
              b = std::max(b, verts[v][d]);
            }
            r[d] = cell_index(d, a);
            r[3 + d] = cell_index(d, b);
          }
        // only the cells of its bounding box that it overlaps (a long slanted triangle's box
        // holds many cells it never comes near, and its plane crosses many of them)
        const Vec &n = tn[t], &a = verts[tv[t][0]];
        for (int i = r[0]; i <= r[3]; i++)
          for (int j = r[1]; j <= r[4]; j++)
            for (int k = r[2]; k <= r[5]; k++) {
              if (!plane_crosses(static_cast<int>(t), i, j, k) ||
                  !overlaps(static_cast<int>(t), i, j, k))
                continue;
              const int c = (i * dims[1] + j) * dims[2] + k;
              if (pass == 0) cstart[c + 1]++;
              else ctris[fill[c]++] = Entry{a, n, static_cast<int>(t)};
            }
      }
      if (pass == 0) {
        for (int c = 0; c < ncell; c++) cstart[c + 1] += cstart[c];
        ctris.assign(cstart.back(), Entry{});
      }
    }
    mark.assign(tv.size(), 0u);
    query = 0;
  }
};

}    // namespace mesh
}    // namespace viscontact

#endif
