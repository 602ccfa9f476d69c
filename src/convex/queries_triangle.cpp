// GJK and EPA for ConvexTriangle<double> against every built-in shape, compiled once (precompiled_queries.hpp).
// One file per first shape, so that the 64 pairs build in parallel.
#include <cdkit/narrowphase/epa.hpp>

namespace cdkit {
CDKIT_WITH_EACH_BUILTIN_SHAPE(CDKIT_GJK_QUERY_INSTANCE, , ::cdkit::ConvexTriangle<double>)
CDKIT_WITH_EACH_BUILTIN_SHAPE(CDKIT_PENETRATION_QUERY_INSTANCE, , ::cdkit::ConvexTriangle<double>)
}  // namespace cdkit
