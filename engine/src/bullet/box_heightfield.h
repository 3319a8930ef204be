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
//   bump smaller than its face, and a face lying on a flat or smooth surface.
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
#include <vector>

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

class BoxHeightfieldAlgorithm : public btCollisionAlgorithm {
  public:
    BoxHeightfieldAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                            const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1,
                            bool swapped)
        : btCollisionAlgorithm(ci), swapped_(swapped) {
        const btCollisionObjectWrapper* box = swapped ? w1 : w0;
        const btCollisionObjectWrapper* field = swapped ? w0 : w1;
        if (m_dispatcher->needsCollision(box->getCollisionObject(), field->getCollisionObject())) {
            manifold_ = m_dispatcher->getNewManifold(box->getCollisionObject(),
                                                     field->getCollisionObject());
        }
    }
    ~BoxHeightfieldAlgorithm() override {
        if (manifold_) m_dispatcher->releaseManifold(manifold_);
    }
    BoxHeightfieldAlgorithm(const BoxHeightfieldAlgorithm&) = delete;
    BoxHeightfieldAlgorithm& operator=(const BoxHeightfieldAlgorithm&) = delete;

    void processCollision(const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1,
                          const btDispatcherInfo&, btManifoldResult* out) override {
        if (!manifold_) return;
        const btCollisionObjectWrapper* box_w = swapped_ ? w1 : w0;
        const btCollisionObjectWrapper* field_w = swapped_ ? w0 : w1;
        const auto* box = static_cast<const btBoxShape*>(box_w->getCollisionShape());
        const auto* field = static_cast<const HeightfieldShape*>(field_w->getCollisionShape());
        const btTransform& tf = field_w->getWorldTransform();
        // the box in the heightfield's frame, where the grid is axis-aligned
        const btTransform tb = tf.inverseTimes(box_w->getWorldTransform());
        const btMatrix3x3& r = tb.getBasis();
        const btVector3& c = tb.getOrigin();
        const btVector3 h = box->getHalfExtentsWithMargin();
        const btScalar reach =
            manifold_->getContactBreakingThreshold() + out->m_closestPointDistanceThreshold;
        const Grid grid(*field);

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
            for (int j = j0; j <= j1; ++j) {
                for (int i = i0; i <= i1; ++i) {
                    btVector3 q;
                    field->getVertex(i, j, q);
                    const btVector3 in_box = (q - c) * r;  // r^T (q - c)
                    if (std::abs(in_box[u]) > h[u] || std::abs(in_box[v]) > h[v]) continue;
                    const btScalar d = sign * in_box[axis] - h[axis];
                    if (!(d < reach) || !grid.summit(*field, i, j, q, -face_normal)) continue;
                    candidates_.push_back({q, -face_normal, d, 8 + j * grid.nx + i});
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
        out->setPersistentManifold(manifold_);
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
        if (manifold_->getNumContacts()) out->refreshContactPoints();
    }

    btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                   btManifoldResult*) override {
        return btScalar(1);
    }

    void getAllContactManifolds(btManifoldArray& manifolds) override {
        if (manifold_) manifolds.push_back(manifold_);
    }

    // makes the algorithm for a box and a HeightfieldShape; Bullet's (`fallback`) for a box and
    // another heightfield shape
    struct CreateFunc : public btCollisionAlgorithmCreateFunc {
        btCollisionAlgorithmCreateFunc* fallback = nullptr;
        btCollisionAlgorithm* CreateCollisionAlgorithm(
            btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* w0,
            const btCollisionObjectWrapper* w1) override {
            const btCollisionShape* field = (m_swapped ? w0 : w1)->getCollisionShape();
            if (!dynamic_cast<const HeightfieldShape*>(field))
                return fallback->CreateCollisionAlgorithm(ci, w0, w1);
            void* mem =
                ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(BoxHeightfieldAlgorithm));
            return new (mem) BoxHeightfieldAlgorithm(ci, w0, w1, m_swapped);
        }
    };

  private:
    // in the heightfield's frame: a point on the surface, the normal there (out of the terrain),
    // the depth of the box's point along it (< 0: inside)
    // `feature`: 0-7 a corner of the box, 8 + j nx + i the grid's vertex (i, j); the manifold
    // keeps it in its points (m_partId1: body 1 is the heightfield)
    struct Candidate {
        btVector3 on_field, normal;
        btScalar depth;
        int feature;
    };

    // the grid as Bullet triangulates it: cell (i, j) is split along its diagonal from vertex
    // (i + 1, j) to (i, j + 1) (btHeightfieldTerrainShape::processAllTriangles without edge
    // flipping, diamond or zigzag subdivision, none of which gaitlab sets)
    struct Grid {
        const HeightfieldShape& field;
        btScalar sx, sy, ox, oy;  // spacing; the grid coordinates of the frame's origin
        int nx, ny;
        explicit Grid(const HeightfieldShape& f)
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
            if (!(gx >= 0 && gy >= 0 && gx <= btScalar(nx - 1) && gy <= btScalar(ny - 1)))
                return false;
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
            i0 = std::max(0, static_cast<int>(std::ceil(lo.x() / sx + ox)));
            i1 = std::min(nx - 1, static_cast<int>(std::floor(hi.x() / sx + ox)));
            j0 = std::max(0, static_cast<int>(std::ceil(lo.y() / sy + oy)));
            j1 = std::min(ny - 1, static_cast<int>(std::floor(hi.y() / sy + oy)));
        }

        // whether no vertex joined to (i, j) by a triangle edge rises above q (vertex (i, j))
        // along `up` by more than kSummitSlope of the edge's length
        bool summit(const HeightfieldShape& f, int i, int j, const btVector3& q,
                    const btVector3& up) const {
            static constexpr int kEdges[6][2] = {{1, 0},  {-1, 0}, {0, 1},
                                                 {0, -1}, {1, -1}, {-1, 1}};
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

    // picks at most 4 candidates into chosen_, returns how many: the deepest (within kDepthTie
    // of the deepest, one the manifold holds, else the first: corners come first), then of those
    // within kDepthBand of it the farthest from it, the one giving the largest triangle, the one
    // giving the largest quadrilateral (held ones' squared sizes count kHold times; ties: the
    // earlier candidate)
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
        // a held candidate's area counts kHold times
        auto weight = [&](int k) { return held_[static_cast<size_t>(k)] ? kHold : btScalar(1); };
        chosen_[0] = first;
        if (n == 1) return 1;
        const btVector3 p0 = at(first).on_field;
        int second = -1;
        btScalar best = -1;
        for (int k = 0; k < n; ++k) {
            const btScalar d2 = (at(k).on_field - p0).length2() * weight(k);
            if (k != first && at(k).depth <= band && d2 > best) {
                best = d2;
                second = k;
            }
        }
        if (second < 0) return 1;
        chosen_[1] = second;
        const btVector3 p1 = at(second).on_field;
        int third = -1;
        best = -1;
        for (int k = 0; k < n; ++k) {
            if (k == first || k == second || at(k).depth > band) continue;
            const btScalar a2 = (at(k).on_field - p0).cross(p1 - p0).length2() * weight(k);
            if (a2 > best) {
                best = a2;
                third = k;
            }
        }
        if (third < 0) return 2;
        chosen_[2] = third;
        const btVector3 p2 = at(third).on_field;
        int fourth = -1;
        best = -1;
        for (int k = 0; k < n; ++k) {
            if (k == first || k == second || k == third || at(k).depth > band) continue;
            const btVector3 p = at(k).on_field;
            // twice the area of the quadrilateral with p as its fourth corner, whichever side
            const btScalar a2 =
                std::max({(p - p0).cross(p1 - p2).length2(), (p - p1).cross(p0 - p2).length2(),
                          (p - p2).cross(p0 - p1).length2()}) *
                weight(k);
            if (a2 > best) {
                best = a2;
                fourth = k;
            }
        }
        if (fourth < 0) return 3;
        chosen_[3] = fourth;
        return 4;
    }

    btPersistentManifold* manifold_ = nullptr;
    bool swapped_;
    std::vector<Candidate> candidates_;
    std::vector<char> held_;
    std::array<int, 4> chosen_{};
};

}  // namespace gaitlab
