// The Sky Texture node (op SKY): Blender's daylight models as Cycles evaluates them, each
// a function of a direction over a table of constants built once at export.
//
// - Perez / Preetham (Preetham, Shirley & Smits 1999): the Perez luminance and
//   chromaticity distributions fitted to turbidity, in CIE xyY, scaled to the zenith
//   values of the paper's formulas. Analytic; the table is 20 numbers.
// - Single scattering (Nishita et al. 1993, Blender's "Nishita" / "Single Scattering"):
//   Rayleigh, Mie and ozone in a spherical atmosphere over 21 wavelengths, integrated
//   along each view ray, tabulated by elevation and azimuth from the sun (the sky is
//   symmetric about the sun's vertical plane) on the texels of the texture Cycles bakes
//   and read back as its kernel reads that texture (the difference is up to several
//   percent near and below the horizon, which a diffuse scene sees), plus the sun's
//   disc from the light that crosses the atmosphere to the viewer.
// - Multiple scattering (Blender 5.x; the model of Fernando Garcia Linan's 2022
//   thesis, "Physically Based Rendering of the Sky and Atmosphere"): air, aerosols and
//   ozone over 4 wavelengths, single scattering plus an analytic fit of the light
//   scattered more than once and of the ground's, integrated along each view ray down
//   to the ground; the same texture layout and read-back, its texels at their centres
//   over the whole sphere.
//
// Directions are in the node's space (after its Vector input): +Z up. Radiance is linear
// Rec.709 (the XYZ of the models through the D65 XYZ-to-Rec.709 matrix, negatives
// clipped, as Cycles' xyz_to_rgb_clamped).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace whitted::sky {

// The mode field "model" of op SKY (ops.h kSkyModelNames), in this order.
enum class Model : uint32_t { kPreetham = 0, kSingleScattering = 1, kHosekWilkie = 2 };

// Perez / Preetham: `sun` the direction towards the sun (unit, +Z up).
std::vector<float> preetham_table(Vec3 sun, float turbidity);

// Hosek / Wilkie: `sun` the direction towards the sun (unit, +Z up; below the horizon
// the sun at the horizon, as Cycles clamps it), `turbidity` clamped to the dataset's
// [1, 10] and `ground_albedo` to [0, 1]. The table: the sun's zenith angle and azimuth,
// then per channel (R, G, B) the parameters A..I and the channel's radiance times
// 2 pi / 683 (Cycles' scale), each cooked from the dataset: a quintic Bezier over its 6
// control points at (elevation / (pi / 2))^(1/3), linear in albedo and in turbidity.
std::vector<float> hosek_wilkie_table(Vec3 sun, float turbidity, float ground_albedo);

// Which of Blender's tabulated skies, baked and its sun disc drawn as that version's
// Cycles does (sky.cpp says the differences): 3.x/4.x's Nishita, 5.x's Single
// Scattering, or 5.x's Multiple Scattering.
enum class Style : uint32_t { kNishita = 0, kSingleScattering = 1, kMultipleScattering = 2 };

struct ScatteringParams {
  float sun_elevation = 0.0f;  // radians above the horizon
  float sun_rotation = 0.0f;   // radians, from +Y towards +X (Blender's Sun Rotation)
  bool sun_disc = true;
  float sun_size = 0.0f;  // the disc's angular diameter, radians
  float sun_intensity = 1.0f;
  float altitude = 0.0f;  // metres (clamped to [1, 59999], Multiple Scattering 99999)
  float air_density = 1.0f;
  float dust_density = 1.0f;  // Blender 5.x's aerosol density
  float ozone_density = 1.0f;
  Style style = Style::kNishita;
};

// The table is the texture Cycles bakes, read as Cycles reads it (bilinear between
// texel centres, clamped at the edges): `columns` texels from the sun's opposite to the
// sun (the texture's other half their mirror image), `rows` from the horizon towards
// the zenith, spaced evenly in sqrt(elevation). Cycles' texture is 512 wide with 128
// such rows.
inline constexpr uint32_t kScatteringColumns = 256;
inline constexpr uint32_t kScatteringRows = 128;

std::vector<float> scattering_table(const ScatteringParams& params,
                                    uint32_t columns = kScatteringColumns,
                                    uint32_t rows = kScatteringRows);

// The direction towards the sun of `params` (unit, +Z up).
Vec3 sun_direction(float elevation, float rotation);

// How many constants the table of `model` at `table` holds, or 0 when the `available`
// constants there do not hold one (the program's check).
size_t table_size(Model model, const float* table, size_t available);

// The sky's radiance towards `direction` (any length; Cycles reads its z as the cosine
// of the zenith angle as it is): finite and non-negative.
Vec3 radiance(Model model, const float* table, Vec3 direction);

// CIE XYZ to linear Rec.709 (D65), negatives clipped.
Vec3 xyz_to_rec709(Vec3 xyz);

// Preetham's zenith luminance (kcd/m^2) for the sun at zenith angle `theta_sun`.
float preetham_zenith_luminance(float theta_sun, float turbidity);

}  // namespace whitted::sky
