// The colour of a black body at a temperature, as Blender's Cycles gives it (issues 48 and
// 49): what op BLACKBODY computes, the Blackbody node (clamped at 0 by its lowering,
// addon/export/nodes/converter_nodes.py) and Principled Volume's blackbody emission
// (addon/export/volume.py) use, and whitted_native.blackbody_rgb gives the add-on.
#pragma once

#include <array>

#include "core/math.h"

namespace whitted {

// The linear Rec.709 colour of a black body at `kelvin`, luminance about 1 (Rec.709
// weights): Cycles' fit of the Planckian locus (svm_math_blackbody_color_rec709, Blender
// 3.2 and later; the same coefficients in 3.4 and 5.x). Between 800 K and 12000 K it is
// piecewise over seven spans of temperature: red and green a / T + b T + c, blue the cubic
// ((a T + b) T + c) T + d; below 800 K the colour at the lower limit (OSL's), from 12000 K
// on the colour there. Not clamped: a channel may be below 0 (the locus lies outside
// Rec.709's gamut; blue below about 1900 K, green below 965 K), as Principled Volume's
// emission takes it; the node clamps it.
inline Vec3 blackbody_rgb(float kelvin) {
  // The coefficients are Blender's, from intern/cycles/kernel/tables.h (blackbody_table_r,
  // blackbody_table_g, blackbody_table_b); each span starts at the temperature beside it.
  struct Span {
    float from;
    std::array<float, 3> r, g;
    std::array<float, 4> b;
  };
  static constexpr std::array<Span, 7> kSpans = {{
      {800.0f,
       {1.61919106e+03f, -2.05010916e-03f, 5.02995757e+00f},
       {-4.88999748e+02f, 6.04330754e-04f, -7.55807526e-02f},
       {5.96945309e-11f, -4.85742887e-08f, -9.70622247e-05f, -4.07936148e-03f}},
      {965.0f,
       {2.48845471e+03f, -1.11330907e-03f, 3.22621544e+00f},
       {-7.55994277e+02f, 3.16730098e-04f, 4.78306139e-01f},
       {2.40430366e-11f, 5.55021075e-08f, -1.98503712e-04f, 2.89312858e-02f}},
      {1167.0f,
       {3.34143193e+03f, -4.86551192e-04f, 1.76486769e+00f},
       {-1.02363977e+03f, 1.20223470e-04f, 9.36662319e-01f},
       {-1.40949732e-11f, 1.89878968e-07f, -3.56632824e-04f, 9.10767778e-02f}},
      {1449.0f,
       {4.09461742e+03f, -1.27446582e-04f, 7.25731635e-01f},
       {-1.26571316e+03f, 4.87340896e-06f, 1.27054498e+00f},
       {-3.61460868e-11f, 2.84822009e-07f, -4.93211319e-04f, 1.56723440e-01f}},
      {1902.0f,
       {4.67028036e+03f, 2.91258199e-05f, 1.26703442e-01f},
       {-1.42529332e+03f, -4.01150431e-05f, 1.43972784e+00f},
       {-1.97075738e-11f, 1.75359352e-07f, -2.50542825e-04f, -2.22783266e-02f}},
      {3315.0f,
       {4.59509185e+03f, 2.87495649e-05f, 1.50345020e-01f},
       {-1.17554822e+03f, -2.16378048e-05f, 1.30408023e+00f},
       {-1.61997957e-13f, -1.64216008e-08f, 3.86216271e-04f, -7.38077418e-01f}},
      {6365.0f,
       {3.78717450e+03f, 9.35907826e-06f, 3.99075871e-01f},
       {-5.00799571e+02f, -4.59832026e-06f, 1.09098763e+00f},
       {6.72650283e-13f, -2.73078809e-08f, 4.24098264e-04f, -7.52335691e-01f}},
  }};
  // Outside the fit: the colours Cycles holds at its ends (NaN falls to the low one).
  if (kelvin >= 12000.0f) return Vec3(0.8262954810464208f, 0.9945080501520986f, 1.566307710274283f);
  if (!(kelvin >= kSpans[0].from)) {
    return Vec3(5.413294490189271f, -0.20319390035873933f, -0.0822535242887164f);
  }
  size_t i = kSpans.size() - 1;
  while (kelvin < kSpans[i].from) --i;
  const Span& s = kSpans[i];
  const float t = kelvin;
  const float inverse = 1.0f / t;
  return Vec3(s.r[0] * inverse + s.r[1] * t + s.r[2], s.g[0] * inverse + s.g[1] * t + s.g[2],
              ((s.b[0] * t + s.b[1]) * t + s.b[2]) * t + s.b[3]);
}

}  // namespace whitted
