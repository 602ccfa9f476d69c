#pragma once
/// \file Shared vocabulary of the benchmark harness: poses, query modes, the Method interface every
/// measured implementation (cdkit or a peer) sits behind, and the timing helpers.
///
/// The harness never sees a peer library's types: each peer lives in its own translation unit and hands
/// back `std::unique_ptr<Method>`s, so FCL's slow headers are compiled once (peers_fcl.cpp).

#include "cdkit/core/math.hpp"
#include "cdkit/core/mesh.hpp"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace cdbench {

/// The moving copy's pose (model frame → world, in double). The fixed copy always sits at the identity;
/// both copies are the same normalised mesh.
struct Pose {
    cdkit::Mat3<double> R = cdkit::Mat3<double>::Identity();
    cdkit::Vec3<double> t = cdkit::Vec3<double>::Zero();
};

/// First contact: stop at the first intersecting triangle pair. All contacts: report every pair.
enum class Mode { first, all };
[[nodiscard]] inline const char* mode_name(Mode m) noexcept { return m == Mode::first ? "first" : "all"; }

/// What one untimed query answered, with its work counters where the implementation exposes them.
struct Outcome {
    bool colliding = false;
    std::size_t contacts = 0;                 ///< intersecting triangle pairs reported (≤ 1 in first mode)
    std::optional<std::uint64_t> bv_tests;    ///< BV overlap tests
    std::optional<std::uint64_t> tri_tests;   ///< triangle–triangle tests
};

/// A timed batch: `reps` identical queries. The answer of the last one is kept so that the harness can
/// check it against the untimed probe (a batch that answers differently would be timing something else).
struct Timed {
    double seconds = 0;
    bool colliding = false;
    std::size_t contacts = 0;
};

/// Build-time facts about one method's model of one mesh.
struct BuildInfo {
    double build_ms = 0;          ///< model construction (validation + tree build), wall clock
    std::size_t tree_bytes = 0;   ///< the tree alone: nodes + triangle order / primitive indices
    std::size_t mesh_bytes = 0;   ///< the geometry the method queries (vertices + indices, in its precision)
    std::size_t nodes = 0;        ///< BV nodes
    bool single_precision = false;  ///< queries run in float (answers may differ from double near contact)
    std::string tree_bytes_note;  ///< how tree_bytes was obtained ("memory_bytes()", "estimate: …")
};

/// One measured implementation, built once per mesh. Both copies of the mesh share one model.
class Method {
public:
    virtual ~Method() = default;
    /// Short identifier used on the command line and in every output, e.g. "cdkit_obb_d", "fcl_obbrss".
    [[nodiscard]] virtual const std::string& name() const noexcept = 0;
    /// "cdkit" or the peer library's name.
    [[nodiscard]] virtual const std::string& family() const noexcept = 0;
    [[nodiscard]] virtual const BuildInfo& build_info() const noexcept = 0;
    /// One untimed query of the moving copy at `pose` against the fixed copy, with work counters.
    [[nodiscard]] virtual Outcome probe(const Pose& pose, Mode mode) = 0;
    /// `reps` timed queries of the same pose (the loop lives inside so no virtual call is timed).
    [[nodiscard]] virtual Timed time(const Pose& pose, Mode mode, std::size_t reps) = 0;
};

using Clock = std::chrono::steady_clock;

/// A sink the optimiser must assume is read: every timed loop folds its answers into it.
inline volatile std::uint64_t g_sink = 0;

/// Compiler barrier: makes the optimiser assume `p` is read and all memory may have changed, so a query
/// cannot be hoisted out of a repetition loop or merged with the previous repetition.
template <class T> inline void clobber(const T& p) noexcept {
#if defined(__GNUC__) || defined(__clang__)
    asm volatile("" : : "r"(&p) : "memory");
#else
    g_sink = g_sink + reinterpret_cast<std::uintptr_t>(&p);
#endif
}

/// Runs `query()` (returning {colliding, contacts}) `reps` times and times the batch.
template <class Query> [[nodiscard]] inline Timed time_batch(std::size_t reps, Query&& query) {
    std::uint64_t acc = 0;
    bool colliding = false;
    std::size_t contacts = 0;
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < reps; ++i) {
        clobber(query);
        const auto [c, n] = query();
        colliding = c;
        contacts = n;
        acc += std::uint64_t(c) + n;
    }
    const auto t1 = Clock::now();
    g_sink = g_sink + acc;
    return {std::chrono::duration<double>(t1 - t0).count(), colliding, contacts};
}

}  // namespace cdbench
