// Reading the values of the XML files' attributes from Lua tables, with the files' meaning: a
// quaternion {w, x, y, z}, an orientation given as yaw or as a quaternion, and robots made of
// bodies and joints (gaitlab.robot.new).
#pragma once

#include <lua.hpp>

#include "gaitlab/types.h"
#include "lua_util.h"

namespace gaitlab::scripting {

/// Field `key` as a unit quaternion: {w, x, y, z} or {w =, x =, y =, z =}, norm 1 within 1e-6
/// (as a file's "w x y z"); `fallback` if absent.
Quat quat_field(lua_State* L, const Fields& f, const char* key, const Quat& fallback);

/// Field `key` as a pose's angle in degrees (0 if absent), at most kMaxAngleDegrees either way.
double pose_angle_field(const Fields& f, const char* key);

/// `yaw` (degrees about +z) or `orientation` (a unit quaternion), not both; identity if neither.
Quat orientation_field(lua_State* L, const Fields& f);

/// Field `key` as a servo's max speed: deg/s in Lua (as every angle a script gives), in
/// (0, kMaxServoSpeed] once in rad/s, refused with that range in deg/s; returned in rad/s,
/// `fallback` (rad/s) if absent.
double servo_speed_field(const Fields& f, const char* key, double fallback);

/// gaitlab.robot.new{ name =, self_collision =, bodies = {...}, joints = {...} }: a robot made
/// of bodies and joints, as a robot file's <body> and <joint> elements make it.
int robot_new(lua_State* L);

}  // namespace gaitlab::scripting
