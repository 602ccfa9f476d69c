#pragma once
/// \file Saving and loading a built InnerSphereTree (the packing is the slow part; a stored tree loads in
/// milliseconds).
///
/// Format (little-endian, version 2): the 8-byte magic "CDKITIST", u32 version, u32 byte-order tag
/// 0x01020304, u64 payload size, u64 FNV-1a checksum of the payload, then the payload: i32 out-degree,
/// f64 mesh volume, u64 sphere count, u64 node count, the spheres (4 × f64), the cell weights (f64), the
/// nodes (5 × f64, 2 × u32). Loading checks the magic, version, byte order, size and checksum, then
/// InnerSphereTree::validate()s the result; any failure raises cdkit::Error naming the file.
/// Version 2 has version 1's layout; the cell weights' calibration strength is derived for the cell-sphere
/// estimate (ist_query.hpp) instead of version 1's weight product, so version 1 files are refused (re-pack).

#include "cdkit/ist/inner_sphere_tree.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace cdkit {

inline constexpr std::uint32_t kInnerSphereTreeFormatVersion = 2;

/// The tree as bytes (the file format above).
[[nodiscard]] std::vector<std::uint8_t> serialize_inner_sphere_tree(const InnerSphereTree& tree);
/// Parses bytes made by serialize_inner_sphere_tree(); `source` names them in errors.
[[nodiscard]] InnerSphereTree deserialize_inner_sphere_tree(const std::vector<std::uint8_t>& bytes,
                                                            const std::string& source = "<memory>");
/// Writes the tree to `path`; throws cdkit::Error naming the path when it cannot be written.
void save_inner_sphere_tree(const InnerSphereTree& tree, const std::string& path);
/// Reads a tree from `path`; throws cdkit::Error naming the path when it is missing, unreadable, of
/// another version, truncated, corrupt (checksum) or inconsistent.
[[nodiscard]] InnerSphereTree load_inner_sphere_tree(const std::string& path);

}  // namespace cdkit
