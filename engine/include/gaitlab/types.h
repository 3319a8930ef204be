// Small value types shared by the whole C++ API: vectors, rotations, poses, and the state of a
// body and of a joint as the physics reports them.
#pragma once

#include <cmath>

namespace gaitlab {

constexpr double kPi = 3.14159265358979323846;

/// Degrees to radians, computed the same way as Lua's math.rad so trajectories match bit for bit.
inline double deg_to_rad(double deg) {
    return deg * (kPi / 180.0);
}
/// Radians to degrees, computed the same way as Lua's math.deg.
inline double rad_to_deg(double rad) {
    return rad * (180.0 / kPi);
}

/// The largest angle a pose may be turned by, either way, in degrees: ten turns (20 pi rad).
/// Files and scripts giving more are refused: such an angle is a mistake, not a pose, and from
/// about 1e16 rad its sine keeps none of the digits written.
inline constexpr double kMaxAngleDegrees = 3600;

/// A 3-vector in metres (or m/s, rad/s, N... as the field that holds it says).
struct Vec3 {
    double x = 0, y = 0, z = 0;

    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
    bool operator!=(const Vec3& o) const { return !(*this == o); }
    double dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
    Vec3 cross(const Vec3& o) const {
        return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x};
    }
    double norm() const { return std::sqrt(dot(*this)); }
};

/// A unit quaternion (w, x, y, z) giving an orientation relative to the world frame.
struct Quat {
    double w = 1, x = 0, y = 0, z = 0;

    /// Rotation of `angle` radians about the unit vector `axis`.
    static Quat from_axis_angle(const Vec3& axis, double angle) {
        const double s = std::sin(angle / 2);
        return {std::cos(angle / 2), axis.x * s, axis.y * s, axis.z * s};
    }
    Quat operator*(const Quat& o) const {
        return {w * o.w - x * o.x - y * o.y - z * o.z, w * o.x + x * o.w + y * o.z - z * o.y,
                w * o.y - x * o.z + y * o.w + z * o.x, w * o.z + x * o.y - y * o.x + z * o.w};
    }
    Quat conjugate() const { return {w, -x, -y, -z}; }
    /// This rotation applied to `v`.
    Vec3 rotate(const Vec3& v) const {
        const Quat p = *this * Quat{0, v.x, v.y, v.z} * conjugate();
        return {p.x, p.y, p.z};
    }
    bool operator==(const Quat& o) const { return w == o.w && x == o.x && y == o.y && z == o.z; }
};

/// The shape of a rigid body or a module: a box, or a cylinder whose axis is the body's x axis.
enum class Shape { box, cylinder };

/// "box" or "cylinder".
inline const char* to_string(Shape s) {
    return s == Shape::box ? "box" : "cylinder";
}

/// A rigid transform: `position` in metres, `orientation` relative to the world frame.
struct Pose {
    Vec3 position;
    Quat orientation;

    /// The point `local`, given in this pose's frame, expressed in the parent frame.
    Vec3 apply(const Vec3& local) const { return position + orientation.rotate(local); }
};

/// State of one rigid body.
struct BodyState {
    Pose pose;
    Vec3 linear_velocity;   ///< m/s, of the centre of mass
    Vec3 angular_velocity;  ///< rad/s
};

/// How well a joint holds together: the solver lets joints drift slightly.
struct JointError {
    double separation = 0;  ///< distance between the pivot seen from each body, m
    double axis_angle = 0;  ///< angle between the axis seen from each body, rad
};

/// Where two solids touch (a robot body, the floor, an object).
struct ContactPoint {
    Vec3 position;     ///< m, world frame
    Vec3 normal;       ///< unit, world frame
    double force = 0;  ///< N: the normal force of the last physics step
    /// N, world frame: the friction force of the last physics step on the body the normal
    /// points into (tangent to the surface; |friction| <= friction coefficient × force where
    /// the contact slides, docs/architecture.md "Contact model")
    Vec3 friction;
    /// m/s, world frame: that body's velocity relative to the other at the point, along the
    /// surface (the slip), after the last step
    Vec3 slip;
};

}  // namespace gaitlab
