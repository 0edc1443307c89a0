// First hits: what a pixel's centre ray meets first (DESIGN.md, "The frame" step 5), or
// through mirrors and clear glass the surface they show (kReplaced). Tracers compute them
// while they render and send them with each tile, so the coordinator reprojects history and
// the denoiser stops at edges without tracing a G-buffer of its own. The centre ray, not a
// jittered sample's: a still view must see the same surface in a pixel every frame.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/math/types.h"

namespace pathfarm {

// One pixel's first hit. Laid out as 12 four-byte words so the OpenCL kernel writes the same
// bytes (tracer-node/opencl/kernels/path_tracer.cl, pf_first_hit).
struct FirstHit {
    static constexpr uint32_t kNone = 0xffffffffu;
    // The pixel shows something a denoiser must not blur over its neighbours: an emitter seen
    // directly, rough glass, or a mirror-like metal or clear glass that shows no surface beyond
    // it (common/render/first_hit.cpp). Its light is not the base colour times a smooth
    // irradiance.
    static constexpr uint32_t kSharp = 1u;
    // Seen through mirrors or clear glass (primary surface replacement, PathTracer::first_hit):
    // the surface beyond them. Its distance is the path's length, so the point lies along the
    // centre ray where the surface appears; its normal is reflected by the mirrors passed, so
    // a flat surface seen in a flat mirror stays flat there; its albedo is the base colour
    // tinted by theirs; no triangle (kNone).
    static constexpr uint32_t kReplaced = 2u;
    // The surface shown (first or replaced) is glossy: GGX alpha below kGlossyMaxAlpha
    // (common/render/path_tracer.h). Part of its light is a reflection that moves over it as
    // the camera does, so its reprojected history lags (the denoiser keeps less of it).
    static constexpr uint32_t kGlossy = 4u;
    float distance = kInfinity;  // along the primary ray; +inf where it escaped
    uint32_t instance = kNone;   // SceneModel index in a backend; the commit's id on the wire
    Vec3 normal{0.0f};           // unit world-space shading normal, facing the camera
    Rgb albedo{0.0f};            // base colour at the hit (textures applied)
    uint32_t flags = 0;          // kSharp, kReplaced, kGlossy
    // The triangle hit (its index in the instance's mesh) and the barycentrics of the point,
    // p = (1-u-v) p0 + u p1 + v p2: where a deforming surface was last frame is the same
    // combination of the triangle's previous vertices (coordinator/converge reprojection).
    uint32_t primitive = kNone;
    float u = 0.0f, v = 0.0f;
    bool hit() const { return instance != kNone; }
    bool sharp() const { return (flags & kSharp) != 0; }
    bool replaced() const { return (flags & kReplaced) != 0; }
    bool glossy() const { return (flags & kGlossy) != 0; }
};
static_assert(sizeof(FirstHit) == 12 * sizeof(float), "FirstHit is the kernel's 12 words");

// Wire form (Tile.first_hits_zstd): planar distance (float32) and instance (uint32), normal and
// albedo as IEEE half floats, flags as a byte, primitive (uint32) and barycentrics as half
// floats, zstd-compressed. Half precision is 1e-3 relative: plenty for reprojection and
// edge-stopping weights, and 29 instead of 48 bytes a pixel. A tracer sends the primitive only
// for surfaces that deformed in the frame (kNone and zero barycentrics elsewhere, which zstd
// reduces to almost nothing): only those need it.
std::string encode_first_hits(const FirstHit* hits, std::size_t count);
// Fails unless `data` holds exactly `count` pixels.
Result<std::vector<FirstHit>> decode_first_hits(const std::string& data, std::size_t count);

}  // namespace pathfarm
