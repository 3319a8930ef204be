// The gaitlab version.
#pragma once

namespace gaitlab {

/// "major.minor.patch" of this build.
const char* version();

}  // namespace gaitlab
