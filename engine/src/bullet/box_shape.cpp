// BoxShape's virtual table is emitted here, and with it btBoxShape::getPlane, inline in Bullet's
// header: GCC warns that its btVector4 may be used uninitialized, on the path of a plane index
// outside 0-5 that btBoxShape::getPlaneEquation leaves unwritten (Bullet's code; no caller
// passes one). The pragma precedes the includes because the warning points into them.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "bullet/box_shape.h"

#include <algorithm>

namespace gaitlab {

btScalar BoxShape::getContactBreakingThreshold(btScalar factor) const {
    const btVector3 h = getHalfExtentsWithMargin();
    return std::min(btBoxShape::getContactBreakingThreshold(factor), h[h.minAxis()]);
}

}  // namespace gaitlab
