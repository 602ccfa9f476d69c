#pragma once
/// \file Umbrella header: everything a user of cdkit needs.

#include "cdkit/core/error.hpp"
#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"
#include "cdkit/io/load_mesh.hpp"
#include "cdkit/bv/aabb.hpp"
#include "cdkit/bv/obb.hpp"
#include "cdkit/bvh/bvh.hpp"
#include "cdkit/bvh/build.hpp"
#include "cdkit/bvh/mesh_model.hpp"
#include "cdkit/bvh/traverse.hpp"
#include "cdkit/narrowphase/triangle.hpp"
#include "cdkit/query.hpp"
