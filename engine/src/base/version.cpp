#include "gaitlab/version.h"

namespace gaitlab {

const char* version() {
    return GAITLAB_VERSION;
}

}  // namespace gaitlab
