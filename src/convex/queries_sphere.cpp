// GJK and EPA for Sphere<double> against every built-in shape, compiled once (precompiled_queries.hpp).
// One file per first shape, so that the 64 pairs build in parallel.
#include <cdkit/narrowphase/epa.hpp>

namespace cdkit {
CDKIT_WITH_EACH_BUILTIN_SHAPE(CDKIT_GJK_QUERY_INSTANCE, , ::cdkit::Sphere<double>)
CDKIT_WITH_EACH_BUILTIN_SHAPE(CDKIT_PENETRATION_QUERY_INSTANCE, , ::cdkit::Sphere<double>)
}  // namespace cdkit
