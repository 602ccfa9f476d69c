#pragma once
/// \file Inlining hints for the hot paths, one spelling for every compiler: GCC and Clang get the attribute,
/// others the plain keyword (the code is correct either way; only speed depends on them).

/// Forces inlining of the few-flop helpers on GJK's per-iteration path (support maps, rotations): at -O2
/// GCC kept several of them out of line, and the call overhead was a measurable share of a query.
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define CDKIT_ALWAYS_INLINE inline
#endif
/// The same for a lambda (placed after its parameter list): GCC kept GJK loop's exit lambda out of line, and
/// the closure it then builds (a pointer per captured local) cost every query ~40 instructions.
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_LAMBDA_INLINE __attribute__((always_inline))
#else
#define CDKIT_LAMBDA_INLINE
#endif
/// Keeps a rare path (GJK's certification of exits without a plane) out of line, off the hot loop's code.
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_COLD_PATH __attribute__((noinline, cold))
#else
#define CDKIT_COLD_PATH
#endif
/// Keeps a path that is not rare but weighs on the code around it (a hull's point location) out of line.
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_NOINLINE __attribute__((noinline))
#else
#define CDKIT_NOINLINE
#endif
/// Inlines everything a function calls into it (the descent's volume test: called from four places, GCC
/// stopped inlining the OBB test there; see bvh/bvh_descent.hpp).
#if defined(__GNUC__) || defined(__clang__)
#define CDKIT_FLATTEN __attribute__((flatten))
#else
#define CDKIT_FLATTEN
#endif
