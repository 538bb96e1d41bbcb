// The tracer's numeric limits, in one place, each with its reason.
//
// What scales with the scene: a secondary ray leaves its surface by that point's own
// floating-point error bound (spawn_ray, core/ray.h), a shadow ray stops a fraction of
// its length short of the light, and the Bump node's step is a fraction of the distance
// from the camera. What does not: the absolute bounds below on coordinates and
// transforms, which keep float32 arithmetic and Embree's range valid; past them geometry
// is dropped (with a warning from the exporter) rather than traced wrongly.
#pragma once

namespace whitted::limits {

// --- bounds that scale with the scene ------------------------------------------------

// A shadow ray to a light sample at distance d ends at d * (1 - kShadowRayShortening), so
// the light's own surface (an area light's quad, an emitter's mesh) cannot block its own
// shadow ray; relative to d, so the same at every scale (about 800 float steps of d).
inline constexpr float kShadowRayShortening = 1e-4f;

// The Bump node reads its height this fraction of the hit's distance from the camera
// away (about one pixel's footprint of a 1000-pixel-wide image at a 53-degree field of
// view: Cycles steps by ray differentials, which Whitted does not carry), and never less
// than kBumpStep * kBumpMinDistance, for a hit at the camera itself.
inline constexpr float kBumpStep = 1e-3f;
inline constexpr float kBumpMinDistance = 1e-3f;

// --- bounds on work ---------------------------------------------------------------------

// Beyond this many cut-out layers along one ray a surface counts as opaque: a bound on
// the walk through stacked alpha cards.
inline constexpr int kMaxTransparentLayers = 64;

// The walk that finds which media enclose a point (a camera inside glass) crosses at most
// this many surfaces; no sane nesting of glass comes near it.
inline constexpr int kMaxMediaCrossings = 1024;

// A shadow feeler's walk through volume bounds (integrator/volume.h) records at most this
// many crossings; beyond them the media are as the last one left them.
inline constexpr int kMaxVolumeCrossings = 64;

// A heterogeneous medium's march along a segment (integrator/heterogeneous.h) stops where
// less than this of the light gets through any further (Cycles' volume throughput
// epsilon): what lies beyond counts as unseen.
inline constexpr float kVolumeOpaque = 1e-6f;

// A volume grid's blocks of 8^3 voxels are found through a dense lattice over its
// voxels' bounding box (scene/volume_grid.h), 4 bytes a block: at most this many blocks
// (512 MiB of lattice, a box of 4096^3 voxels); a grid spread wider is refused with a
// message (scene/vdb_file.cpp) rather than exhausting memory.
inline constexpr long long kMaxGridBlocks = 1LL << 27;

// --- absolute bounds: float32 and Embree ----------------------------------------------

// The exporter drops triangles with an object-space coordinate beyond 1e7
// (MAX_COORDINATE in addon/export/mesh.py, which gives the float32 reasoning); it is
// Python's to apply, named here so every bound is listed in one file.

// Embree aborts the process on a ray with a NaN or a component above 1.8e18 (also in an
// instance's object space). Ray origins and directions beyond kMaxRayComponent are not
// traced (accel/embree.cpp); instances whose linear part or its inverse exceeds
// kMaxInstanceLinear, or whose translation exceeds kMaxInstanceTranslation, are left out
// (scene.cpp), so object-space rays stay below 2e17.
inline constexpr float kMaxRayComponent = 1e9f;
inline constexpr float kMaxInstanceLinear = 1e8f;
inline constexpr float kMaxInstanceTranslation = 1e9f;

// Texture lookups with a texel coordinate beyond this are black (the float-to-int
// conversion of a larger one is undefined).
inline constexpr float kMaxTexelCoordinate = 1e8f;

// A medium's coefficient a program computes is at most this per unit of length (an
// infinite one this): times any step of a sane scene it stays finite in float32, so
// exp(-sigma d) is 0 and never a NaN (a material's constant ones are checked finite).
inline constexpr float kMaxCoefficient = 1e30f;

}  // namespace whitted::limits
