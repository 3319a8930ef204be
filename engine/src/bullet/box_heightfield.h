// The box-on-heightfield collider of every gaitlab world (a module or a box on terrain), in
// place of Bullet's convex-concave path (btConvexConcaveCollisionAlgorithm), in the spirit of
// box_plane.h. Bullet's path runs GJK/EPA between the box and each triangle under it and hands
// the pair's one 4-point manifold one point per triangle, the deepest: for a face lying on
// triangles that point is an arbitrary one of the face, different every step, and both shapes'
// collision margins (1 mm each side) count, so a small box jittered at up to 0.1-0.17 m/s and
// rested 1.0-1.5 mm above the surface (docs/architecture.md, "Contact points").
// This collider measures the box against the heightfield's own triangles (Bullet's
// triangulation of the grid, its vertices from btHeightfieldTerrainShape::getVertex):
// - each corner of the box (with its margin) against the plane of the triangle under it: a point
//   at the corner's true place, depth along the triangle's normal;
// - each grid vertex under the box's downward face that is a local summit of the terrain seen
//   from that face (no neighbouring vertex higher along the face's inward normal, within
//   kSummitSlope): a point at the vertex, depth along the face's normal. These hold a box on a
//   bump smaller than its face, and a face lying on a flat or smooth surface;
// - each point where a ridge of the grid (an edge whose triangles fold down from it by more
//   than kSummitSlope) crosses the border of that face: the ridge against the box's edge, depth
//   along the normal of both edges. These hold a face lying across a ridge between vertices.
// Of these, at most 4 go into the manifold: the deepest (the first within kDepthTie of it, box
// corners first), then, among the points within kDepthBand of its depth, the ones that span the
// largest area, a point the manifold already holds preferred (kHold); the manifold keeps no
// point from an earlier step that is not among them (each kept one keeps its warm-start
// impulse). Each point's feature (corner or grid vertex) is stored in the manifold point, so a
// clone, which copies the manifolds, chooses as its original does.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "bullet/box_collider.h"

namespace gaitlab {

/// Bullet's heightfield shape with its grid size readable (Bullet keeps it protected).
class HeightfieldShape : public btHeightfieldTerrainShape {
  public:
    /// `heights` (samples_x * samples_y, row by row along x) must outlive the shape.
    HeightfieldShape(int samples_x, int samples_y, const float* heights, btScalar lo, btScalar hi)
        : btHeightfieldTerrainShape(samples_x, samples_y, heights, lo, hi, 2, false) {}
    int samples_x() const { return m_heightStickWidth; }
    int samples_y() const { return m_heightStickLength; }
};

// two candidate depths closer than this are equal (the earlier candidate is the deepest), m
inline constexpr btScalar kDepthTie = btScalar(0.0001);
// the points chosen lie within this of the deepest one's depth, m
inline constexpr btScalar kDepthBand = btScalar(0.0002);
// a point the manifold holds from the last step is kept unless another spans this much more
// squared distance or area (twice the distance or area)
inline constexpr btScalar kHold = btScalar(4);
// a grid vertex is a summit seen from a face if no neighbour rises above it towards the face by
// more than this slope (sine of the angle): a face lying on a flat or smooth surface touches
// every vertex under it
inline constexpr btScalar kSummitSlope = btScalar(0.02);

/// The grid of a HeightfieldShape as Bullet triangulates it: cell (i, j) is split along its
/// diagonal from vertex (i + 1, j) to (i, j + 1) (btHeightfieldTerrainShape::processAllTriangles
/// without edge flipping, diamond or zigzag subdivision, none of which gaitlab sets). The
/// collider below reads it, and so does the range sensor's test of a point under the surface
/// (sensor_probes.cpp).
struct HeightfieldGrid {
    const HeightfieldShape& field;
    btScalar sx, sy, ox, oy;  // spacing; the grid coordinates of the frame's origin
    int nx, ny;
    explicit HeightfieldGrid(const HeightfieldShape& f)
        : field(f),
          sx(f.getLocalScaling().x()),
          sy(f.getLocalScaling().y()),
          ox(btScalar(f.samples_x() - 1) / 2),
          oy(btScalar(f.samples_y() - 1) / 2),
          nx(f.samples_x()),
          ny(f.samples_y()) {}

    // a vertex of the triangle under p (in x and y) and its upward unit normal; false if p
    // is not over the grid
    bool triangle_under(const btVector3& p, btVector3& a, btVector3& n) const {
        const btScalar gx = p.x() / sx + ox, gy = p.y() / sy + oy;
        if (!(gx >= 0 && gy >= 0 && gx <= btScalar(nx - 1) && gy <= btScalar(ny - 1))) return false;
        const int i = std::min(static_cast<int>(gx), nx - 2);
        const int j = std::min(static_cast<int>(gy), ny - 2);
        btVector3 b, d;
        if ((gx - btScalar(i)) + (gy - btScalar(j)) <= 1) {
            field.getVertex(i, j, a);
            field.getVertex(i + 1, j, b);
            field.getVertex(i, j + 1, d);
        } else {
            field.getVertex(i + 1, j + 1, a);
            field.getVertex(i, j + 1, b);
            field.getVertex(i + 1, j, d);
        }
        n = (b - a).cross(d - a);
        if (n.z() < 0) n = -n;
        n.normalize();
        return true;
    }

    // the vertices whose x and y lie within [lo, hi]
    void vertex_range(const btVector3& lo, const btVector3& hi, int& i0, int& i1, int& j0,
                      int& j1) const {
        // clamped before the conversion: a box far away or not finite (a simulation about
        // to be stopped as diverged) gives an empty range, not an overflow
        const auto index = [](btScalar g, int n) {
            return g > btScalar(n) ? n : g > btScalar(-2) ? static_cast<int>(g) : -2;
        };
        i0 = std::max(0, index(std::ceil(lo.x() / sx + ox), nx));
        i1 = std::min(nx - 1, index(std::floor(hi.x() / sx + ox), nx));
        j0 = std::max(0, index(std::ceil(lo.y() / sy + oy), ny));
        j1 = std::min(ny - 1, index(std::floor(hi.y() / sy + oy), ny));
    }

    // whether edge `e` from grid point (i, j) (0: to (i + 1, j), 1: to (i, j + 1), 2: to
    // (i - 1, j + 1)), from a to b, is a ridge: its two triangles fold down from it by more
    // than kSummitSlope (an edge on the grid's border counts). Elsewhere the grid points and
    // the corners hold a face
    bool ridge(const HeightfieldShape& f, int i, int j, int e, const btVector3& a,
               const btVector3& b) const {
        // the third grid point of each triangle of the edge
        static constexpr int kThird[3][2][2] = {
            {{0, 1}, {1, -1}}, {{1, 0}, {-1, 1}}, {{-1, 0}, {0, 1}}};
        btVector3 w[2];
        for (int k = 0; k < 2; ++k) {
            const int x = i + kThird[e][k][0], y = j + kThird[e][k][1];
            if (x < 0 || y < 0 || x >= nx || y >= ny) return true;
            f.getVertex(x, y, w[k]);
        }
        btVector3 n = (b - a).cross(w[0] - a);
        if (n.z() < 0) n = -n;
        const btVector3 to = w[1] - a;
        return to.dot(n) < -kSummitSlope * to.length() * n.length();
    }

    // whether no vertex joined to (i, j) by a triangle edge rises above q (vertex (i, j))
    // along `up` by more than kSummitSlope of the edge's length
    bool summit(const HeightfieldShape& f, int i, int j, const btVector3& q,
                const btVector3& up) const {
        static constexpr int kEdges[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
        for (const auto& e : kEdges) {
            const int a = i + e[0], b = j + e[1];
            if (a < 0 || b < 0 || a >= nx || b >= ny) continue;
            btVector3 w;
            f.getVertex(a, b, w);
            const btVector3 edge = w - q;
            if (edge.dot(up) > kSummitSlope * edge.length()) return false;
        }
        return true;
    }
};

class BoxHeightfieldAlgorithm : public BoxCollider<BoxHeightfieldAlgorithm, HeightfieldShape> {
  public:
    BoxHeightfieldAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                            const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1,
                            bool swapped)
        : BoxCollider(ci, w0, w1, swapped) {}

    // makes the algorithm for a box and a HeightfieldShape; Bullet's (its `setting`, the
    // fallback) for a box and another heightfield shape
    using CreateFunc = BoxCollider::CreateFunc<btCollisionAlgorithmCreateFunc*>;
    static btCollisionAlgorithm* create(btCollisionAlgorithmConstructionInfo& ci,
                                        const btCollisionObjectWrapper* w0,
                                        const btCollisionObjectWrapper* w1, bool swapped,
                                        btCollisionAlgorithmCreateFunc* fallback) {
        const btCollisionShape* field = (swapped ? w0 : w1)->getCollisionShape();
        if (!dynamic_cast<const HeightfieldShape*>(field))
            return fallback->CreateCollisionAlgorithm(ci, w0, w1);
        return make(ci, w0, w1, swapped);
    }

  private:
    friend class BoxCollider<BoxHeightfieldAlgorithm, HeightfieldShape>;

    void collide(const btBoxShape* box, const btTransform& box_at, const HeightfieldShape* field,
                 const btTransform& tf, btScalar reach, btManifoldResult* out) {
        // the box in the heightfield's frame, where the grid is axis-aligned
        const btTransform tb = tf.inverseTimes(box_at);
        const btMatrix3x3& r = tb.getBasis();
        const btVector3& c = tb.getOrigin();
        const btVector3 h = box->getHalfExtentsWithMargin();
        const HeightfieldGrid grid(*field);

        candidates_.clear();
        // the corners against the triangles under them
        for (int k = 0; k < 8; ++k) {
            const btVector3 local((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                                  (k & 4) ? h.z() : -h.z());
            const btVector3 p = tb * local;
            btVector3 a, n;
            if (!grid.triangle_under(p, a, n)) continue;
            const btScalar d = (p - a).dot(n);
            if (d < reach) candidates_.push_back({p - n * d, n, d, k});
        }
        // the grid vertices under the downward face that are summits seen from it
        int axis = 0;
        for (int i = 1; i < 3; ++i) {
            if (std::abs(r[2][i]) > std::abs(r[2][axis])) axis = i;
        }
        const btScalar sign = r[2][axis] > 0 ? btScalar(-1) : btScalar(1);  // outward: down
        const btVector3 face_normal = r.getColumn(axis) * sign;             // outward
        if (face_normal.z() < 0) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            // the face's bounding rectangle on the grid
            btVector3 lo(BT_LARGE_FLOAT, BT_LARGE_FLOAT, 0),
                hi(-BT_LARGE_FLOAT, -BT_LARGE_FLOAT, 0);
            for (int k = 0; k < 4; ++k) {
                btVector3 local(0, 0, 0);
                local[axis] = sign * h[axis];
                local[u] = (k & 1) ? h[u] : -h[u];
                local[v] = (k & 2) ? h[v] : -h[v];
                const btVector3 p = tb * local;
                lo.setMin(p);
                hi.setMax(p);
            }
            int i0, i1, j0, j1;
            grid.vertex_range(lo, hi, i0, i1, j0, j1);
            // the grid points of the face's rectangle and one more row around it (the ends of
            // every grid edge that crosses the face's border), in both frames, read once
            const int x0 = std::max(0, i0 - 1), x1 = std::min(grid.nx - 1, i1 + 1);
            const int y0 = std::max(0, j0 - 1), y1 = std::min(grid.ny - 1, j1 + 1);
            const int w = x1 - x0 + 1;
            if (w > 0 && y1 >= y0) {
                const size_t count = static_cast<size_t>(w) * static_cast<size_t>(y1 - y0 + 1);
                on_grid_.resize(count);
                in_box_.resize(count);
                auto at = [&](int i, int j) {
                    return static_cast<size_t>((j - y0) * w + (i - x0));
                };
                for (int j = y0; j <= y1; ++j) {
                    for (int i = x0; i <= x1; ++i) {
                        field->getVertex(i, j, on_grid_[at(i, j)]);
                        in_box_[at(i, j)] = (on_grid_[at(i, j)] - c) * r;  // r^T (q - c)
                    }
                }
                for (int j = std::max(j0, 0); j <= std::min(j1, grid.ny - 1); ++j) {
                    for (int i = std::max(i0, 0); i <= std::min(i1, grid.nx - 1); ++i) {
                        const btVector3& q = on_grid_[at(i, j)];
                        const btVector3& in_box = in_box_[at(i, j)];
                        if (std::abs(in_box[u]) > h[u] || std::abs(in_box[v]) > h[v]) continue;
                        const btScalar d = sign * in_box[axis] - h[axis];
                        if (!(d < reach) || !grid.summit(*field, i, j, q, -face_normal)) continue;
                        candidates_.push_back({q, -face_normal, d, 8 + j * grid.nx + i});
                    }
                }
                // where the grid's edges cross the face's border: a terrain edge against an
                // edge of the box (a ridge between grid points, under the face but without a
                // grid point there), its depth along their common normal
                const int edges_first = 8 + grid.nx * grid.ny;
                for (int j = y0; j <= y1; ++j) {
                    for (int i = x0; i <= x1; ++i) {
                        // the edges from grid point (i, j): along +x, along +y, and the cells'
                        // diagonal to (i - 1, j + 1)
                        for (int e = 0; e < 3; ++e) {
                            const int i2 = e == 0 ? i + 1 : e == 1 ? i : i - 1;
                            const int j2 = e == 0 ? j : j + 1;
                            if (i2 < x0 || i2 > x1 || j2 > y1) continue;
                            const btVector3& a = on_grid_[at(i, j)];
                            const btVector3& b = on_grid_[at(i2, j2)];
                            add_crossings(tb, h, axis, sign, face_normal, a, b, in_box_[at(i, j)],
                                          in_box_[at(i2, j2)], reach,
                                          edges_first + ((j * grid.nx + i) * 3 + e) * 4,
                                          [&] { return grid.ridge(*field, i, j, e, a, b); });
                        }
                    }
                }
            }
        }
        // which candidates the manifold holds from the last step: kept in preference to others
        // (a point that comes and goes loses the impulse it starts the solver with)
        held_.assign(candidates_.size(), 0);
        for (size_t k = 0; k < candidates_.size(); ++k) {
            for (int m = 0; m < manifold_->getNumContacts(); ++m) {
                if (manifold_->getContactPoint(m).m_partId1 == candidates_[k].feature) held_[k] = 1;
            }
        }
        const int keep = choose();

        // the manifold holds exactly the chosen points: an old point of another feature goes
        // first (a kept one keeps its warm-start impulse: the manifold matches a new point with
        // the nearest old one)
        auto is_chosen = [&](int feature) {
            for (int k = 0; k < keep; ++k) {
                if (candidates_[static_cast<size_t>(chosen_[static_cast<size_t>(k)])].feature ==
                    feature)
                    return true;
            }
            return false;
        };
        for (int m = manifold_->getNumContacts() - 1; m >= 0; --m) {
            if (!is_chosen(manifold_->getContactPoint(m).m_partId1))
                manifold_->removeContactPoint(m);
        }
        for (int k = 0; k < keep; ++k) {
            const Candidate& p = candidates_[static_cast<size_t>(chosen_[static_cast<size_t>(k)])];
            if (swapped_) {
                out->setShapeIdentifiersA(p.feature, 0);
            } else {
                out->setShapeIdentifiersB(p.feature, 0);
            }
            out->addContactPoint(tf.getBasis() * p.normal, tf * p.on_field, p.depth);
        }
    }

    // in the heightfield's frame: a point on the surface, the normal there (out of the terrain),
    // the depth of the box's point along it (< 0: inside)
    // the points where terrain edge a-b (heightfield frame; la, lb in the box's) crosses the
    // border of the box's face
    // `axis`, `sign` (outward normal `face_normal`), seen along that normal: each against the
    // box's edge there, depth along the normal of both edges; features `feature` + the side
    // only if `ridge()` says the edge is a ridge (asked only of an edge that crosses the border)
    template <typename Ridge>
    void add_crossings(const btTransform& tb, const btVector3& h, int axis, btScalar sign,
                       const btVector3& face_normal, const btVector3& a, const btVector3& b,
                       const btVector3& la, const btVector3& lb, btScalar reach, int feature,
                       Ridge ridge) {
        const btMatrix3x3& r = tb.getBasis();
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        // most edges lie inside the face or beyond one of its sides
        const bool a_in = std::abs(la[u]) <= h[u] && std::abs(la[v]) <= h[v];
        const bool b_in = std::abs(lb[u]) <= h[u] && std::abs(lb[v]) <= h[v];
        if (a_in && b_in) return;
        for (const int k : {u, v}) {
            if ((la[k] > h[k] && lb[k] > h[k]) || (la[k] < -h[k] && lb[k] < -h[k])) return;
        }
        // Liang-Barsky against the sides u = -h, u = +h, v = -h, v = +h
        const btScalar du = lb[u] - la[u], dv = lb[v] - la[v];
        const btScalar p[4] = {-du, du, -dv, dv};
        const btScalar q[4] = {la[u] + h[u], h[u] - la[u], la[v] + h[v], h[v] - la[v]};
        btScalar t0 = 0, t1 = 1;
        int s0 = -1, s1 = -1;
        for (int k = 0; k < 4; ++k) {
            if (p[k] == 0) {
                if (q[k] < 0) return;
                continue;
            }
            const btScalar t = q[k] / p[k];
            if (p[k] < 0 && t > t0) {
                t0 = t;
                s0 = k;
            } else if (p[k] > 0 && t < t1) {
                t1 = t;
                s1 = k;
            }
        }
        if (t0 > t1 || (s0 < 0 && s1 < 0) || !ridge()) return;
        const btVector3 edge = b - a;
        for (const auto& [t, side] : {std::pair<btScalar, int>{t0, s0}, {t1, s1}}) {
            if (side < 0) continue;  // a grid point inside the face: taken as a vertex or not
            const btVector3 box_edge = r.getColumn(side < 2 ? v : u);
            btVector3 n = box_edge.cross(edge);
            const btScalar len = n.length();
            if (!(len > btScalar(1e-6) * edge.length())) continue;  // parallel
            n /= len;
            // out of the terrain into the box; an edge steeper than 60 degrees to the face is
            // left to the corners
            if (n.dot(face_normal) > 0) n = -n;
            if (-n.dot(face_normal) < btScalar(0.5)) continue;
            const btVector3 at = a + edge * t;
            btVector3 local = (at - tb.getOrigin()) * r;
            local[axis] = sign * h[axis];
            if (side < 2) {
                local[u] = side == 0 ? -h[u] : h[u];
            } else {
                local[v] = side == 2 ? -h[v] : h[v];
            }
            const btScalar d = (tb * local - at).dot(n);
            if (d < reach) candidates_.push_back({at, n, d, feature + side});
        }
    }

    // `feature`: 0-7 a corner of the box, 8 + j nx + i the grid's vertex (i, j), then 4 per grid
    // edge (the side of the face it crosses); the manifold
    // keeps it in its points (m_partId1: body 1 is the heightfield)
    struct Candidate {
        btVector3 on_field, normal;
        btScalar depth;
        int feature;
    };

    // picks at most 4 candidates into chosen_, returns how many: the deepest (within kDepthTie
    // of the deepest, one the manifold holds, else the first: corners come first), then of those
    // within kDepthBand of it the farthest from it, the one giving the largest triangle, the one
    // giving the largest quadrilateral (widest())
    int choose() {
        const int n = static_cast<int>(candidates_.size());
        if (n == 0) return 0;
        auto at = [&](int k) -> const Candidate& { return candidates_[static_cast<size_t>(k)]; };
        btScalar deepest = at(0).depth;
        for (int k = 1; k < n; ++k)
            deepest = std::min(deepest, at(k).depth);
        // only the points about to touch when the deepest does: a point farther away, chosen
        // for the area it spans, would take the place of one that touches first
        const btScalar band = deepest + kDepthBand;
        int first = -1;
        for (int k = 0; k < n; ++k) {
            if (at(k).depth > deepest + kDepthTie) continue;
            if (first < 0 || (held_[static_cast<size_t>(k)] && !held_[static_cast<size_t>(first)]))
                first = k;
        }
        chosen_[0] = first;
        if (n == 1) return 1;
        const btVector3 p0 = at(first).on_field;
        const int second = widest(1, band, [&](const btVector3& p) { return (p - p0).length2(); });
        if (second < 0) return 1;
        chosen_[1] = second;
        const btVector3 p1 = at(second).on_field;
        const int third =
            widest(2, band, [&](const btVector3& p) { return (p - p0).cross(p1 - p0).length2(); });
        if (third < 0) return 2;
        chosen_[2] = third;
        const btVector3 p2 = at(third).on_field;
        // twice the area of the quadrilateral with p as its fourth corner, whichever side
        const int fourth = widest(3, band, [&](const btVector3& p) {
            return std::max({(p - p0).cross(p1 - p2).length2(), (p - p1).cross(p0 - p2).length2(),
                             (p - p2).cross(p0 - p1).length2()});
        });
        if (fourth < 0) return 3;
        chosen_[3] = fourth;
        return 4;
    }

    // the candidate not among the first `chosen` of chosen_, with depth within `band`, whose
    // on_field point gives the largest squared size `size(point)`, a held one's counting kHold
    // times (ties: the earlier candidate); -1 if there is none
    template <typename Size>
    int widest(int chosen, btScalar band, Size size) const {
        int best = -1;
        btScalar best_size = -1;
        for (int k = 0; k < static_cast<int>(candidates_.size()); ++k) {
            const Candidate& p = candidates_[static_cast<size_t>(k)];
            if (p.depth > band) continue;
            bool taken = false;
            for (int c = 0; c < chosen; ++c)
                taken = taken || chosen_[static_cast<size_t>(c)] == k;
            if (taken) continue;
            const btScalar s =
                size(p.on_field) * (held_[static_cast<size_t>(k)] ? kHold : btScalar(1));
            if (s > best_size) {
                best_size = s;
                best = k;
            }
        }
        return best;
    }

    std::vector<Candidate> candidates_;
    std::vector<char> held_;
    std::vector<btVector3> on_grid_, in_box_;  // grid points near the face (collide)
    std::array<int, 4> chosen_{};
};

}  // namespace gaitlab
