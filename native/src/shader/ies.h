// IES photometric profiles: the IES Texture node (Blender's ShaderNodeTexIES), which lamp
// node trees use to shape a lamp's light by a measured luminaire's distribution.
//
// The add-on parses the profile (addon/export/ies.py, as Cycles' IESFile reads type B and
// C files and completes their symmetries) into a table in the program's constants:
//
//   h_count, v_count, h_count horizontal angles, v_count vertical angles (radians,
//   ascending), then for each horizontal angle its v_count intensities.
//
// Evaluation is Cycles' (kernel/util/ies.h): Catmull-Rom interpolation along the
// vertical angles at the four horizontal angles around the point, then along those,
// negative results clamped to 0. The neighbours past the table's edges differ between
// Cycles' versions, and `legacy` chooses:
// - legacy (Cycles 3.x): the horizontal angles always wrap round the circle, the vertical
//   ones across the first angle (its mirror image) and are held at the last; zero past
//   the last vertical angle only.
// - otherwise (Cycles 4.x+): zero outside the table's angles; a neighbour past an edge
//   wraps only where the edge lies within 1e-7 of the full circle or a pole, compared in
//   float as Cycles compares (so a table closed at exactly 360 or 180 degrees does not
//   wrap there), and is held where it does not: the edge's own value, and past the last
//   horizontal angle the interval's first row, as Cycles holds it.
#pragma once

#include <cstddef>

#include "core/math.h"

namespace whitted::ies {

// The number of floats of the table at `table`, or 0 where the `available` floats there
// do not hold one (fewer than 2 angles each way, angles not ascending or not finite).
size_t table_size(const float* table, size_t available);

// The table's intensity at horizontal angle `h` and vertical angle `v` (radians).
float intensity(const float* table, float h, float v, bool legacy);

// The IES Texture's Fac per unit Strength for a lookup vector (not necessarily unit): the
// vertical angle from the lamp's -Z axis (0: straight down), the horizontal one about Z,
// as Cycles' node measures them (acos(-z); atan2(x, y) + pi). 0 for a zero vector.
float lookup(const float* table, const Vec3& vector, bool legacy);

}  // namespace whitted::ies
