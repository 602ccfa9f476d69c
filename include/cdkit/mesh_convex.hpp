#pragma once
/// \file Mesh–convex queries: collide, distance and penetration between a MeshModel (any BV) and any
/// support-mapped convex shape (mesh_convex/*.hpp; docs/contacts.md).

#include "cdkit/mesh_convex/collide.hpp"
#include "cdkit/mesh_convex/distance.hpp"
#include "cdkit/mesh_convex/penetration.hpp"
#include "cdkit/mesh_convex/result.hpp"
