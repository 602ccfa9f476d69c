#pragma once
/// \file FCL, behind the harness's Method interface. Only peers_fcl.cpp includes FCL's headers.

#include "bench.hpp"

#include <functional>

namespace cdbench {

/// Names of the FCL methods, in output order ("fcl_obbrss" first: it is the peer every ratio refers to).
[[nodiscard]] std::vector<std::string> fcl_method_names();

/// Builds the FCL methods for which `wanted(name)` is true: one BVHModel<BV> of `mesh` (already normalised),
/// queried with fcl::collide on both copies.
[[nodiscard]] std::vector<std::unique_ptr<Method>> make_fcl_methods(
    const cdkit::TriangleMesh<double>& mesh, const std::function<bool(const std::string&)>& wanted);

/// FCL's version string (FCL_VERSION).
[[nodiscard]] std::string fcl_version();

}  // namespace cdbench
