// The gaitlab version.
#pragma once

namespace gaitlab {

/// "major.minor.patch" of this build.
const char* version();

/// The source commit this build was made from (`git describe --always --dirty`, e.g.
/// "05b675f" or "05b675f-dirty"), refreshed at every build; "unknown" when not built from git.
const char* source_commit();

}  // namespace gaitlab
