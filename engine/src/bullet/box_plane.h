// The box-on-plane collider of every gaitlab world (a module on the floor), in place of
// Bullet's general convex-plane path with its multipoint search (ContactConfiguration in
// coulomb_solver.h, which every other pair still takes). Header-only, like coulomb_solver.h, so
// that the benchmarks' raw Bullet loop (bench/raw_bullet_loop.cpp) steps exactly the engine's
// physics; docs/performance.md, section 13, measures it (the same points, 13 % of the
// instructions).
#pragma once

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>

#include "bullet/box_collider.h"
#include "bullet/box_heightfield.h"
#include "bullet/coulomb_solver.h"

namespace gaitlab {

/// Which corners of a box touching a plane become contact points.
enum class BoxPlanePoints {
    /// every corner closer to the plane than the manifold's breaking threshold (at most 4:
    /// the corners of the face or edge on the plane), the points Bullet's multipoint search
    /// finds, but computed directly
    touching,
    /// the 4 corners of a face lying flat (their heights within kFlatTolerance of each other),
    /// otherwise at most the deepest 2
    flat_or_two,
};

// the spread of the 4 touching corners' heights below which a face counts as flat, m
inline constexpr btScalar kFlatTolerance = btScalar(0.0002);

// The 8 corners of the box (with its margin, as Bullet's support function gives them) are
// measured against the plane directly: no support-vertex search under 6 tilted copies of the
// box. Each corner within reach is a point at its true place and depth, handed to the manifold
// as Bullet's convex-plane algorithm hands its points (the manifold matches them with the
// points it holds, which keeps their warm-start impulses).
class BoxPlaneAlgorithm : public BoxCollider<BoxPlaneAlgorithm, btStaticPlaneShape> {
  public:
    BoxPlaneAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                      const btCollisionObjectWrapper* w0, const btCollisionObjectWrapper* w1,
                      bool swapped, BoxPlanePoints points)
        : BoxCollider(ci, w0, w1, swapped), points_(points) {}

    // makes the algorithm with the points its `setting` says (default: touching)
    using CreateFunc = BoxCollider::CreateFunc<BoxPlanePoints>;

  private:
    friend class BoxCollider<BoxPlaneAlgorithm, btStaticPlaneShape>;

    void collide(const btBoxShape* box, const btTransform& tb, const btStaticPlaneShape* plane,
                 const btTransform& tp, btScalar reach, btManifoldResult* out) {
        const btVector3 normal = tp.getBasis() * plane->getPlaneNormal();
        const btScalar level = plane->getPlaneConstant() + normal.dot(tp.getOrigin());
        const btVector3 h = box->getHalfExtentsWithMargin();
        const btMatrix3x3& r = tb.getBasis();
        // the normal's component along each box axis, times the half extent
        const btScalar ax = r.tdotx(normal) * h.x(), ay = r.tdoty(normal) * h.y(),
                       az = r.tdotz(normal) * h.z();
        const btScalar centre = normal.dot(tb.getOrigin()) - level;
        // the corners within reach, deepest first (ties in corner order: deterministic)
        struct Corner {
            btScalar depth;
            int index;
        };
        std::array<Corner, 8> found{};
        int n = 0;
        for (int k = 0; k < 8; ++k) {
            const btScalar d =
                centre + ((k & 1) ? ax : -ax) + ((k & 2) ? ay : -ay) + ((k & 4) ? az : -az);
            if (!(d < reach)) continue;
            // insertion into the sorted ones: a stable order, equal depths by corner index
            int at = n++;
            for (; at > 0 && found[static_cast<size_t>(at - 1)].depth > d; --at)
                found[static_cast<size_t>(at)] = found[static_cast<size_t>(at - 1)];
            found[static_cast<size_t>(at)] = {d, k};
        }
        int keep = std::min(n, 4);
        if (points_ == BoxPlanePoints::flat_or_two && keep > 2 &&
            !(keep == 4 && found[3].depth - found[0].depth <= kFlatTolerance)) {
            keep = 2;
        }
        for (int i = 0; i < keep; ++i) {
            const Corner& c = found[static_cast<size_t>(i)];
            const btVector3 local((c.index & 1) ? h.x() : -h.x(), (c.index & 2) ? h.y() : -h.y(),
                                  (c.index & 4) ? h.z() : -h.z());
            const btVector3 on_plane = tb * local - normal * c.depth;
            out->addContactPoint(normal, on_plane, c.depth);
        }
    }

    BoxPlanePoints points_;
};

/// The collision configuration with the box-plane collider above for box-plane pairs, the
/// box-heightfield collider (box_heightfield.h) for a box and a HeightfieldShape, the engine's
/// ContactConfiguration for everything else.
class BoxPlaneConfiguration : public ContactConfiguration {
  public:
    explicit BoxPlaneConfiguration(BoxPlanePoints points = BoxPlanePoints::touching) {
        box_plane_.setting = points;
        plane_box_.setting = points;
        plane_box_.m_swapped = true;
        box_field_.setting = ContactConfiguration::getCollisionAlgorithmCreateFunc(
            BOX_SHAPE_PROXYTYPE, TERRAIN_SHAPE_PROXYTYPE);
        field_box_.setting = ContactConfiguration::getCollisionAlgorithmCreateFunc(
            TERRAIN_SHAPE_PROXYTYPE, BOX_SHAPE_PROXYTYPE);
        field_box_.m_swapped = true;
    }
    btCollisionAlgorithmCreateFunc* getCollisionAlgorithmCreateFunc(int type0, int type1) override {
        if (type0 == BOX_SHAPE_PROXYTYPE && type1 == STATIC_PLANE_PROXYTYPE) return &box_plane_;
        if (type0 == STATIC_PLANE_PROXYTYPE && type1 == BOX_SHAPE_PROXYTYPE) return &plane_box_;
        if (type0 == BOX_SHAPE_PROXYTYPE && type1 == TERRAIN_SHAPE_PROXYTYPE) return &box_field_;
        if (type0 == TERRAIN_SHAPE_PROXYTYPE && type1 == BOX_SHAPE_PROXYTYPE) return &field_box_;
        return ContactConfiguration::getCollisionAlgorithmCreateFunc(type0, type1);
    }

  private:
    BoxPlaneAlgorithm::CreateFunc box_plane_, plane_box_;
    BoxHeightfieldAlgorithm::CreateFunc box_field_, field_box_;
};

}  // namespace gaitlab
