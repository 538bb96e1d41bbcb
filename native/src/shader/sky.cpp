#include "shader/sky.h"

#include "shader/hosek_wilkie_data.inc"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <thread>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace whitted::sky {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kHalfPi = kPi / 2.0f;

// ---------------------------------------------------------------------------------------
// Perez / Preetham.

// Table offsets: the sun's zenith angle and azimuth (from +Y towards +X), the zenith's
// Y, x, y (each divided by its Perez function at the zenith), then five Perez
// coefficients each for Y, x and y.
enum PreethamSlot : size_t { kSunTheta = 0, kSunPhi, kZenith, kPerez = kZenith + 3 };
constexpr size_t kPreethamSize = kPerez + 15;

// The Perez distribution: theta the view's zenith angle, gamma its angle from the sun.
float perez(const float* lam, float theta, float gamma) {
  const float cos_gamma = std::cos(gamma);
  return (1.0f + lam[0] * std::exp(lam[1] / std::cos(theta))) *
         (1.0f + lam[2] * std::exp(lam[3] * gamma) + lam[4] * cos_gamma * cos_gamma);
}

// The zenith chromaticity polynomial of Preetham's appendix: rows of T^2, T, 1 by
// theta^3, theta^2, theta, 1.
float zenith_chromaticity(const std::array<std::array<float, 4>, 3>& m, float theta, float t) {
  const std::array<float, 4> powers = {theta * theta * theta, theta * theta, theta, 1.0f};
  float sum = 0.0f;
  const std::array<float, 3> tp = {t * t, t, 1.0f};
  for (size_t i = 0; i < 3; ++i) {
    float row = 0.0f;
    for (size_t j = 0; j < 4; ++j) row += m[i][j] * powers[j];
    sum += tp[i] * row;
  }
  return sum;
}

// Zenith and azimuth (from +Y towards +X) of a direction, as Cycles' sky reads them:
// the zenith angle from z alone.
float zenith_angle(Vec3 d) {
  return std::acos(std::clamp(d.z, -1.0f, 1.0f));
}
float azimuth(Vec3 d) {
  return std::atan2(d.x, d.y);
}

// The angle between the directions of zenith angles and azimuths (theta, phi) and
// (sun_theta, sun_phi).
float angle_from_sun(float theta, float phi, float sun_theta, float sun_phi) {
  const float cos_gamma = std::sin(theta) * std::sin(sun_theta) * std::cos(sun_phi - phi) +
                          std::cos(theta) * std::cos(sun_theta);
  return std::acos(std::clamp(cos_gamma, -1.0f, 1.0f));
}

// The zenith angle at which the analytic models read a direction below the horizon (the
// horizon's value there), as Cycles.
constexpr float kHorizonTheta = kHalfPi - 0.001f;

Vec3 preetham(const float* t, Vec3 direction) {
  float theta = zenith_angle(direction);
  const float gamma = angle_from_sun(theta, azimuth(direction), t[kSunTheta], t[kSunPhi]);
  theta = std::min(theta, kHorizonTheta);
  const float luminance = t[kZenith] * perez(t + kPerez, theta, gamma);
  const float x = t[kZenith + 1] * perez(t + kPerez + 5, theta, gamma);
  const float y = t[kZenith + 2] * perez(t + kPerez + 10, theta, gamma);
  if (y == 0.0f) return Vec3(0.0f);
  return xyz_to_rec709(Vec3(x / y * luminance, luminance, (1.0f - x - y) / y * luminance));
}

// ---------------------------------------------------------------------------------------
// Hosek / Wilkie.

// Table offsets: the sun's zenith angle and azimuth, then per channel (R, G, B) the 9
// parameters A..I and the channel's radiance (times Cycles' 2 pi / 683).
enum HosekSlot : size_t { kHosekSunTheta = 0, kHosekSunPhi, kHosekChannels };
constexpr size_t kHosekParameters = 9;
constexpr size_t kHosekChannel = kHosekParameters + 1;
constexpr size_t kHosekSize = kHosekChannels + 3 * kHosekChannel;

// The dataset's extents: turbidities 1..10, ground albedos 0 and 1, 6 control points.
constexpr size_t kHosekTurbidities = 10;
constexpr size_t kHosekControlPoints = 6;

// Their extended Perez formula: `p` the parameters A..I, `cos_theta` the view's zenith
// cosine, `gamma` its angle from the sun.
float hosek_wilkie_formula(const float* p, float cos_theta, float gamma) {
  const float cos_gamma = std::cos(gamma);
  const float rayleigh = cos_gamma * cos_gamma;
  const float mie =
      (1.0f + rayleigh) / std::pow(1.0f + p[8] * p[8] - 2.0f * p[8] * cos_gamma, 1.5f);
  return (1.0f + p[0] * std::exp(p[1] / (cos_theta + 0.01f))) *
         (p[2] + p[3] * std::exp(p[4] * gamma) + p[5] * rayleigh + p[6] * mie +
          p[7] * std::sqrt(cos_theta));
}

Vec3 hosek_wilkie(const float* t, Vec3 direction) {
  const float theta = zenith_angle(direction);
  const float gamma = angle_from_sun(theta, azimuth(direction), t[kHosekSunTheta], t[kHosekSunPhi]);
  const float cos_theta = std::cos(std::min(theta, kHorizonTheta));
  Vec3 rgb;
  for (size_t c = 0; c < 3; ++c) {
    const float* channel = t + kHosekChannels + c * kHosekChannel;
    rgb[c] = hosek_wilkie_formula(channel, cos_theta, gamma) * channel[kHosekParameters];
  }
  return glm::max(rgb, Vec3(0.0f));
}

// A value of the dataset `data` (turbidity x albedo x control point x channel x
// `count` values) cooked for the sun: each of the `count` values of `channel` at
// Bezier parameter `s` over the control points, linear in albedo and turbidity.
void cook(const double* data, size_t count, size_t channel, double turbidity, double albedo,
          double s, float* out) {
  const auto at = [&](size_t turbidity_index, size_t albedo_index, size_t value) {
    // The quintic Bezier (Bernstein form) over the 6 control points.
    constexpr std::array<double, kHosekControlPoints> kBinomial = {1, 5, 10, 10, 5, 1};
    double sum = 0.0;
    for (size_t k = 0; k < kHosekControlPoints; ++k) {
      const size_t index =
          (((turbidity_index * 2 + albedo_index) * kHosekControlPoints + k) * 3 + channel) * count +
          value;
      sum += kBinomial[k] * std::pow(1.0 - s, static_cast<double>(5 - k)) *
             std::pow(s, static_cast<double>(k)) * data[index];
    }
    return sum;
  };
  const auto lower = static_cast<size_t>(turbidity);  // 1..10
  const double fraction = turbidity - static_cast<double>(lower);
  const size_t upper = std::min(lower + 1, kHosekTurbidities);
  for (size_t v = 0; v < count; ++v) {
    const auto blend = [&](size_t t) {
      return (1.0 - albedo) * at(t - 1, 0, v) + albedo * at(t - 1, 1, v);
    };
    out[v] = static_cast<float>((1.0 - fraction) * blend(lower) + fraction * blend(upper));
  }
}

// ---------------------------------------------------------------------------------------
// Single scattering: the atmosphere of Nishita et al. as Blender parameterises it.

constexpr double kEarthRadius = 6360e3;       // m
constexpr double kAtmosphereRadius = 6420e3;  // m
constexpr float kRayleighHeight = 8e3f;       // scale heights, m
constexpr float kMieHeight = 1.2e3f;
constexpr float kMieScattering = 2e-5f;  // m^-1; extinction 1.11 times that
constexpr float kMieExtinction = 1.11f * kMieScattering;
constexpr float kMieG = 0.76f;  // the aerosols' anisotropy
constexpr int kViewSteps = 32;  // midpoint steps along a view ray
constexpr size_t kWavelengths = 21;
constexpr float kWavelengthStep = 20.0f;  // nm, 380 to 780

// Per wavelength: the sun's irradiance above the atmosphere (W m^-2 nm^-1), the Rayleigh
// scattering coefficient at sea level (m^-1), the ozone absorption coefficient (m^-1)
// and the CIE 1931 colour matching functions.
constexpr std::array<float, kWavelengths> kSolarIrradiance = {
    1.45756829855592995315f, 1.56596305559738380175f, 1.65148449067670455293f,
    1.71496242737209314555f, 1.75797983805020541226f, 1.78256407885924539336f,
    1.79095108475838560302f, 1.78541550133410664714f, 1.76815554864306845317f,
    1.74122069647250410362f, 1.70647127164943679389f, 1.66556087452739887134f,
    1.61993437242451854274f, 1.57083597368892080581f, 1.51932335059305478886f,
    1.46628494965214395407f, 1.41245852740172450623f, 1.35844961970384092709f,
    1.30474913844739281998f, 1.25174963272610817455f, 1.19975998755420620867f};
constexpr std::array<float, kWavelengths> kRayleigh = {
    5.424820087636473e-05f, 4.418549866505454e-05f, 3.635151910165377e-05f, 3.017929012024763e-05f,
    2.526320226989157e-05f, 2.130859310621843e-05f, 1.809838025320633e-05f, 1.547057129129042e-05f,
    1.330284977336850e-05f, 1.150184784075764e-05f, 9.99557429990163e-06f,  8.72799973630707e-06f,
    7.65513700977967e-06f,  6.74217203751443e-06f,  5.96134125832052e-06f,  5.29034598065810e-06f,
    4.71115687557433e-06f,  4.20910481110487e-06f,  3.77218381260133e-06f,  3.39051255477280e-06f,
    3.05591531679811e-06f};
constexpr std::array<float, kWavelengths> kOzone = {
    3.25126849861e-09f,    5.85395365047e-09f,    1.977191155085e-08f,   7.309568762914e-08f,
    2.0084561514287e-07f,  4.0383958096161e-07f,  6.3551335912363e-07f,  9.6707041180970e-07f,
    1.54797400424410e-06f, 2.09038647223331e-06f, 2.46128056164565e-06f, 2.73551299461512e-06f,
    2.15125863128643e-06f, 1.59051840791988e-06f, 1.12356197979857e-06f, 7.3527551487574e-07f,
    4.6450130357806e-07f,  3.3096079921048e-07f,  2.2512612292678e-07f,  1.4879129266490e-07f,
    1.6828623364192e-07f};
constexpr std::array<std::array<float, 3>, kWavelengths> kColorMatching = {{
    {0.00136800000f, 0.00003900000f, 0.00645000100f},
    {0.01431000000f, 0.00039600000f, 0.06785001000f},
    {0.13438000000f, 0.00400000000f, 0.64560000000f},
    {0.34828000000f, 0.02300000000f, 1.74706000000f},
    {0.29080000000f, 0.06000000000f, 1.66920000000f},
    {0.09564000000f, 0.13902000000f, 0.81295010000f},
    {0.00490000000f, 0.32300000000f, 0.27200000000f},
    {0.06327000000f, 0.71000000000f, 0.07824999000f},
    {0.29040000000f, 0.95400000000f, 0.02030000000f},
    {0.59450000000f, 0.99500000000f, 0.00390000000f},
    {0.91630000000f, 0.87000000000f, 0.00165000100f},
    {1.06220000000f, 0.63100000000f, 0.00080000000f},
    {0.85444990000f, 0.38100000000f, 0.00019000000f},
    {0.44790000000f, 0.17500000000f, 0.00002000000f},
    {0.16490000000f, 0.06100000000f, 0.00000000000f},
    {0.04677000000f, 0.01700000000f, 0.00000000000f},
    {0.01135916000f, 0.00410200000f, 0.00000000000f},
    {0.00289932700f, 0.00104700000f, 0.00000000000f},
    {0.00069007860f, 0.00024920000f, 0.00000000000f},
    {0.00016615050f, 0.00006000000f, 0.00000000000f},
    {0.00004150994f, 0.00001499000f, 0.00000000000f},
}};

// Optical depth towards the sun by 8-point Gauss-Laguerre quadrature over the path to
// the atmosphere's edge (the densities fall off about exponentially along it), its
// nodes scaled so that the last lies inside: nodes x_i / 25 of the path, weights
// w_i e^(x_i) / 25.
constexpr std::array<float, 8> kQuadratureNodes = {0.006811185292f, 0.03614807107f, 0.09004346519f,
                                                   0.1706680068f,   0.2818362161f,  0.4303406404f,
                                                   0.6296271457f,   0.9145252695f};
constexpr std::array<float, 8> kQuadratureWeights = {0.01750893642f, 0.04135477391f, 0.06678839063f,
                                                     0.09507698807f, 0.1283416365f,  0.1707430204f,
                                                     0.2327233347f,  0.3562490486f};

using DVec3 = glm::dvec3;
using Spectrum = std::array<float, kWavelengths>;

// Relative densities of air (Rayleigh), aerosols (Mie) and ozone at `height` metres.
Vec3 densities(double height) {
  const auto h = static_cast<float>(height);
  return {std::exp(-h / kRayleighHeight), std::exp(-h / kMieHeight),
          std::max(0.0f, 1.0f - std::fabs(h - 25e3f) / 15e3f)};
}

double to_atmosphere_edge(const DVec3& p, const DVec3& d) {
  const double b = glm::dot(p, d);
  const double c = glm::dot(p, p) - kAtmosphereRadius * kAtmosphereRadius;
  return -b + std::sqrt(std::max(0.0, b * b - c));
}

bool meets_ground(const DVec3& p, const DVec3& d) {
  if (d.z >= 0.0) return false;
  const double b = glm::dot(p, d);
  return b * b - (glm::dot(p, p) - kEarthRadius * kEarthRadius) >= 0.0;
}

Vec3 optical_depth(const DVec3& p, const DVec3& d) {
  const double length = to_atmosphere_edge(p, d);
  Vec3 depth(0.0f);
  for (size_t i = 0; i < kQuadratureNodes.size(); ++i) {
    const DVec3 q = p + static_cast<double>(kQuadratureNodes[i]) * length * d;
    depth += densities(glm::length(q) - kEarthRadius) * kQuadratureWeights[i];
  }
  return depth * static_cast<float>(length);
}

Vec3 to_xyz(const Spectrum& s) {
  Vec3 xyz(0.0f);
  for (size_t i = 0; i < kWavelengths; ++i) {
    xyz += Vec3(kColorMatching[i][0], kColorMatching[i][1], kColorMatching[i][2]) * s[i];
  }
  return xyz * kWavelengthStep;
}

struct Atmosphere {
  DVec3 eye;
  Vec3 scale;  // air, dust, ozone densities
};

float rayleigh_phase(float mu) {
  return 3.0f / (16.0f * kPi) * (1.0f + mu * mu);
}

float mie_phase(float mu) {  // Cornette-Shanks
  const float g2 = kMieG * kMieG;
  return 3.0f * (1.0f - g2) * (1.0f + mu * mu) /
         (8.0f * kPi * (2.0f + g2) * std::pow(1.0f + g2 - 2.0f * kMieG * mu, 1.5f));
}

// The sunlight scattered once towards the eye along `view` (XYZ).
Vec3 inscattered(const Atmosphere& a, const DVec3& view, const DVec3& sun) {
  const double step = to_atmosphere_edge(a.eye, view) / kViewSteps;
  const auto fstep = static_cast<float>(step);
  const auto mu = static_cast<float>(glm::dot(view, sun));
  const float rayleigh = rayleigh_phase(mu);
  const float mie = mie_phase(mu);
  Spectrum spectrum{};
  Vec3 depth(0.0f);  // from the eye to the current point
  for (int i = 0; i < kViewSteps; ++i) {
    const DVec3 p = a.eye + (i + 0.5) * step * view;
    const Vec3 density = a.scale * densities(glm::length(p) - kEarthRadius);
    depth += fstep * density;
    if (meets_ground(p, sun)) continue;
    const Vec3 total = depth + a.scale * optical_depth(p, sun);
    for (size_t w = 0; w < kWavelengths; ++w) {
      const float transmittance =
          std::exp(-(total.x * kRayleigh[w] + total.y * kMieExtinction + total.z * kOzone[w]));
      const float scattering =
          rayleigh * density.x * kRayleigh[w] + mie * density.y * kMieScattering;
      spectrum[w] += transmittance * scattering * kSolarIrradiance[w] * fstep;
    }
  }
  return to_xyz(spectrum);
}

// The sun's radiance seen at `elevation` (XYZ): its irradiance spread over the disc's
// solid angle, through air and aerosols (Cycles leaves ozone out of the disc).
Vec3 sun_radiance(const Atmosphere& a, float elevation, float solid_angle) {
  const DVec3 towards(std::cos(elevation), 0.0, std::sin(elevation));
  const Vec3 depth = optical_depth(a.eye, towards);
  Spectrum spectrum{};
  for (size_t w = 0; w < kWavelengths; ++w) {
    const float tau = kRayleigh[w] * depth.x * a.scale.x + kMieExtinction * depth.y * a.scale.y;
    spectrum[w] = kSolarIrradiance[w] * std::exp(-tau) / solid_angle;
  }
  return to_xyz(spectrum);
}

// ---------------------------------------------------------------------------------------
// Multiple scattering (5.x): Garcia Linan's atmosphere in km, at 630, 560, 490 and 430 nm.

using Vec4 = glm::vec4;

constexpr float kMsEarthRadius = 6371.0f;      // km
constexpr float kMsAtmosphereHeight = 100.0f;  // km
constexpr float kMsAtmosphereRadius = kMsEarthRadius + kMsAtmosphereHeight;
constexpr int kMsSteps = 64;        // midpoint steps along a ray
constexpr int kMsLutCosines = 256;  // transmittance table: cosine of the zenith angle
constexpr int kMsLutHeights = 64;   // by height (0 to the atmosphere's top)
constexpr float kMsAerosolG = 0.8f;
constexpr float kMsGroundAlbedo = 0.3f;
const Vec4 kMsSunIrradiance(1.679f, 1.828f, 1.986f, 1.307f);
const Vec4 kMsMolecularScattering(6.605e-3f, 1.067e-2f, 1.842e-2f,
                                  3.156e-2f);  // km^-1 at sea level
const Vec4 kMsOzoneCrossSection(3.472e-25f, 3.914e-25f, 1.349e-25f, 11.03e-27f);
constexpr float kMsOzoneDobson = 334.5f;
const Vec4 kMsAerosolAbsorption(2.8722e-24f, 4.6168e-24f, 7.9706e-24f, 1.3578e-23f);
const Vec4 kMsAerosolScattering(1.5908e-22f, 1.7711e-22f, 2.0942e-22f, 2.4033e-22f);
constexpr float kMsAerosolDensity = 1.3681e20f;
constexpr float kMsAerosolBackground = 2e6f;
constexpr float kMsAerosolHeight = 0.73f;  // km
// Each wavelength's radiance to XYZ.
constexpr std::array<std::array<float, 3>, 4> kMsToXyz = {{
    {53.386917738564668f, 22.981337506691025f, 0.0f},
    {43.904844466369358f, 71.347795700053394f, 0.102506867965741f},
    {1.6137278251608962f, 18.422960591455485f, 31.742921188390806f},
    {20.762668673810577f, 2.3614213523314369f, 110.48009643252140f},
}};

Vec3 ms_to_xyz(Vec4 l) {
  Vec3 xyz(0.0f);
  for (int i = 0; i < 4; ++i) xyz += Vec3(kMsToXyz[i][0], kMsToXyz[i][1], kMsToXyz[i][2]) * l[i];
  return xyz;
}

// The distance from `p` along `d` to the sphere of `radius` about the Earth's centre
// (the nearer crossing ahead), or -1 for none.
float ms_to_sphere(Vec3 p, Vec3 d, float radius) {
  const float b = glm::dot(p, d);
  const float c = glm::dot(p, p) - radius * radius;
  if (c > 0.0f && b > 0.0f) return -1.0f;
  const float disc = b * b - c;
  if (disc < 0.0f) return -1.0f;
  return disc >= b * b ? -b + std::sqrt(disc) : -b - std::sqrt(disc);
}

// The sun in the bake's frame: towards -X, `cos_zenith` up.
Vec3 ms_sun(float cos_zenith) {
  return {-std::sqrt(std::max(0.0f, 1.0f - cos_zenith * cos_zenith)), 0.0f, cos_zenith};
}

class MultipleScattering {
 public:
  explicit MultipleScattering(Vec3 scale) : scale_(scale) {}

  struct Coefficients {
    Vec4 scattering_air, scattering_aerosol, extinction;
  };

  // Air (Rayleigh), ozone and aerosols at `altitude` km.
  Coefficients at(float altitude) const {
    const float aerosol =
        kMsAerosolDensity *
        (std::exp(-altitude / kMsAerosolHeight) + kMsAerosolBackground / kMsAerosolDensity) *
        scale_.y;
    const float log_h = std::log(std::max(altitude, 1e-4f));
    const float ozone =
        3.78547397e20f * std::exp(-(log_h - 3.22261f) * (log_h - 3.22261f) * 5.55555555f - log_h);
    const Vec4 air = kMsMolecularScattering *
                     (std::exp(-0.07771971f * std::pow(altitude, 1.16364243f)) * scale_.x);
    const Vec4 scattering_aerosol = kMsAerosolScattering * aerosol;
    const Vec4 extinction = kMsAerosolAbsorption * aerosol + scattering_aerosol +
                            kMsOzoneCrossSection * (kMsOzoneDobson * ozone * scale_.z) + air;
    return {air, scattering_aerosol, extinction};
  }

  // The transmittance to the sun `cos_zenith` up from `height` (0 to 1 of the atmosphere).
  Vec4 transmittance(float cos_zenith, float height) const {
    const Vec3 sun = ms_sun(cos_zenith);
    const Vec3 origin(0.0f, 0.0f, kMsEarthRadius + (kMsAtmosphereRadius - kMsEarthRadius) * height);
    const float step = ms_to_sphere(origin, sun, kMsAtmosphereRadius) / kMsSteps;
    Vec4 depth(0.0f);
    for (int i = 0; i < kMsSteps; ++i) {
      const Vec3 x = origin + sun * ((static_cast<float>(i) + 0.5f) * step);
      depth += at(std::max(glm::length(x) - kMsEarthRadius, 0.0f)).extinction * step;
    }
    return glm::exp(-depth);
  }

  void tabulate() {
    lut_.resize(static_cast<size_t>(kMsLutCosines) * kMsLutHeights);
    for (int y = 0; y < kMsLutHeights; ++y) {
      for (int x = 0; x < kMsLutCosines; ++x) {
        lut_[static_cast<size_t>(y) * kMsLutCosines + x] =
            transmittance(2.0f * static_cast<float>(x) / (kMsLutCosines - 1) - 1.0f,
                          static_cast<float>(y) / (kMsLutHeights - 1));
      }
    }
  }

  // The sunlight scattered towards the eye at `origin` along `view` over `length` km.
  Vec4 inscattered(Vec3 sun, Vec3 origin, Vec3 view, float length) const {
    const float mu = glm::dot(-view, sun);
    const float air_phase = 3.0f / (16.0f * kPi) * (1.0f + mu * mu);
    const float g2 = kMsAerosolG * kMsAerosolG;
    const float den = 1.0f + g2 + 2.0f * kMsAerosolG * mu;
    const float aerosol_phase = (1.0f - g2) / (4.0f * kPi * den * std::sqrt(den));
    const float dt = length / kMsSteps;
    Vec4 radiance(0.0f);
    Vec4 transmitted(1.0f);
    for (int i = 0; i < kMsSteps; ++i) {
      const Vec3 x = origin + view * ((static_cast<float>(i) + 0.5f) * dt);
      const float r = glm::length(x);
      const float altitude = std::max(r - kMsEarthRadius, 0.0f);
      const float height = altitude / kMsAtmosphereHeight;
      const float cos_sun = glm::dot(x / r, sun);
      const Coefficients k = at(altitude);
      const Vec4 to_sun = lookup(cos_sun, height);
      const Vec4 more = multiple(cos_sun, height, r);
      const Vec4 source =
          kMsSunIrradiance * (k.scattering_air * (air_phase * to_sun + more) +
                              k.scattering_aerosol * (aerosol_phase * to_sun + more));
      const Vec4 step = glm::exp(-dt * k.extinction);
      // Each step's in-scattering integrated exactly over its extinction (Hillaire 2016).
      radiance += transmitted * (source - source * step) / glm::max(k.extinction, Vec4(1e-7f));
      transmitted *= step;
    }
    return radiance;
  }

 private:
  Vec4 texel(int x, int y) const { return lut_[static_cast<size_t>(y) * kMsLutCosines + x]; }

  Vec4 lookup(float cos_zenith, float height) const {
    const float x = (kMsLutCosines - 1) * std::clamp(cos_zenith * 0.5f + 0.5f, 0.0f, 1.0f);
    const float y = (kMsLutHeights - 1) * std::clamp(height, 0.0f, 1.0f);
    const int x0 = static_cast<int>(x);
    const int y0 = static_cast<int>(y);
    const int x1 = std::min(x0 + 1, kMsLutCosines - 1);
    const int y1 = std::min(y0 + 1, kMsLutHeights - 1);
    const float fx = x - static_cast<float>(x0);
    const float fy = y - static_cast<float>(y0);
    const Vec4 bottom = glm::mix(texel(x0, y0), texel(x1, y0), fx);
    return glm::mix(bottom, glm::mix(texel(x0, y1), texel(x1, y1), fx), fy);
  }

  // The light scattered more than once, per unit scattering: the ground's (lit by the
  // sun, seen over the solid angle it subtends from `r` km) and an analytic fit of the
  // atmosphere's own.
  Vec4 multiple(float cos_zenith, float height, float r) const {
    const float ratio = kMsEarthRadius / r;
    const float omega = 2.0f * kPi * (1.0f - std::sqrt(1.0f - ratio * ratio));
    const Vec4 ground_to_sun = lookup(cos_zenith, 0.0f);
    const Vec4 ground_to_here = lookup(1.0f, 0.0f) / lookup(1.0f, height);
    const Vec4 ground = (omega / (4.0f * kPi)) * (kMsGroundAlbedo / kPi) * ground_to_sun *
                        ground_to_here * cos_zenith;
    const Vec4 atmosphere =
        0.02f * Vec4(0.217f, 0.347f, 0.594f, 1.0f) / (1.0f + 5.0f * std::exp(-17.92f * cos_zenith));
    return atmosphere + ground;
  }

  Vec3 scale_;  // air, aerosol, ozone densities
  std::vector<Vec4> lut_;
};

// Table offsets of the single-scattering model.
enum ScatteringSlot : size_t {
  kSun = 0,           // xyz, unit
  kSunElevation = 3,  //
  kSunDiameter = 4,   // negative: no disc
  kSunIntensity = 5,  //
  kDiscBottom = 6,    // XYZ at the disc's lowest point
  kDiscTop = 9,       // and at its highest
  kStyle = 12,        // Style
  kColumns = 13,      // texels from the sun's opposite to the sun (half the texture's width)
  kRows = 14,         // texels from the horizon up
  kDiscLowest = 15,   // 5.x: the elevation above which the disc is drawn
  kScatteringHeader = 16,
};

Vec3 lerp(Vec3 a, Vec3 b, float t) {
  return a + (b - a) * t;
}

// The elevation of the table's row `r`: 5.x's Single Scattering texture holds the sky
// at pi/2 (r / rows)^2 in the `rows` rows above its middle; 3.x's, a texture of `rows`
// rows, at (pi/2 + half a row's step) (r / rows)^2; Multiple Scattering's, 2 `rows`
// rows over the whole sphere, at its rows' centres, pi/2 l |l| for l from -1 to 1.
double row_elevation(Style style, uint32_t r, uint32_t rows) {
  const double top = std::numbers::pi / 2.0;
  if (style == Style::kMultipleScattering) {
    const double l = (r + 0.5) / rows - 1.0;
    return top * l * std::fabs(l);
  }
  const double s = static_cast<double>(r) / rows;
  return (style == Style::kNishita ? top + top / (2.0 * rows) : top) * s * s;
}

// 5.x's texture below its middle row `row` (of `rows` there): the horizon's colour
// faded by (1 - 2.5 sin(e))^3 to black at sin(e) = 0.4, e the row's depth
// pi/2 (1 - row / rows)^2.
float below_horizon_fade(uint32_t row, uint32_t rows) {
  const float s = 1.0f - static_cast<float>(row) / static_cast<float>(rows);
  const float z = std::sin(kHalfPi * s * s);
  if (!(z < 0.4f)) return 0.0f;
  const float fade = 1.0f - 2.5f * z;
  return fade * fade * fade;
}

// The baked texture (XYZ) at texel (`x`, `y`), both clamped to it (Cycles' Extend):
// 2 * columns wide, its right half the left's mirror image; 3.x's `rows` high, 5.x's
// twice that (Single Scattering's lower half the horizon's row faded).
Vec3 texel(const float* t, int x, int y) {
  const auto columns = static_cast<int>(t[kColumns]);
  const auto rows = static_cast<int>(t[kRows]);
  const auto style = static_cast<Style>(t[kStyle]);
  x = std::clamp(x, 0, 2 * columns - 1);
  if (x >= columns) x = 2 * columns - 1 - x;
  y = std::clamp(y, 0, (style == Style::kNishita ? rows : 2 * rows) - 1);
  float scale = 1.0f;
  if (style == Style::kSingleScattering) {
    if (y < rows) scale = below_horizon_fade(static_cast<uint32_t>(y), static_cast<uint32_t>(rows));
    y = std::max(y - rows, 0);
  }
  const float* c = t + kScatteringHeader + 3 * (static_cast<size_t>(y) * columns + x);
  return Vec3(c[0], c[1], c[2]) * scale;
}

// The sky (XYZ) at `elevation` and azimuth `relative` in [0, pi] from the sun, read from
// the baked texture as Cycles' kernel reads it: the sun's azimuth at the middle of its
// width, the elevation through sqrt (5.x signed, over its height; 3.x over the upper
// hemisphere, clamped), bilinear between texel centres.
Vec3 sky_xyz(const float* t, float elevation, float relative) {
  const float width = 2.0f * t[kColumns];
  const bool v5 = static_cast<Style>(t[kStyle]) != Style::kNishita;
  const float height = v5 ? 2.0f * t[kRows] : t[kRows];
  const float u = 0.5f - std::clamp(relative, 0.0f, kPi) / (2.0f * kPi);
  const float root = std::sqrt(std::min(std::fabs(elevation) / kHalfPi, 1.0f));
  const float v = v5 ? 0.5f + 0.5f * std::copysign(root, elevation) : root;
  const float px = u * width - 0.5f;
  const float py = v * height - 0.5f;
  const float fx = std::floor(px);
  const float fy = std::floor(py);
  const auto x = static_cast<int>(fx);
  const auto y = static_cast<int>(fy);
  return lerp(lerp(texel(t, x, y), texel(t, x + 1, y), px - fx),
              lerp(texel(t, x, y + 1), texel(t, x + 1, y + 1), px - fx), py - fy);
}

Vec3 single_scattering(const float* t, Vec3 d) {
  const Vec3 sun(t[kSun], t[kSun + 1], t[kSun + 2]);
  const float elevation = kHalfPi - zenith_angle(d);
  float relative = std::fabs(std::remainder(azimuth(d) - azimuth(sun), 2.0f * kPi));
  if (!std::isfinite(relative)) relative = 0.0f;
  const auto style = static_cast<Style>(t[kStyle]);
  if (style == Style::kNishita && d.z < 0.0f) {
    // 3.x below the horizon: the horizon's colour fading to black at z = -0.4.
    if (d.z < -0.4f) return Vec3(0.0f);
    const float fade = 1.0f + 2.5f * d.z;
    return xyz_to_rec709(sky_xyz(t, 0.0f, relative)) * (fade * fade * fade);
  }
  const Vec3 sky = sky_xyz(t, elevation, relative);
  const float diameter = t[kSunDiameter];
  if (diameter < 0.0f) return xyz_to_rec709(sky);
  const float half = diameter / 2.0f;
  const float angle = std::atan2(glm::length(glm::cross(d, sun)), glm::dot(d, sun));
  if (!(angle < half)) return xyz_to_rec709(sky);
  const Vec3 bottom(t[kDiscBottom], t[kDiscBottom + 1], t[kDiscBottom + 2]);
  const Vec3 top(t[kDiscTop], t[kDiscTop + 1], t[kDiscTop + 2]);
  const float sun_elevation = t[kSunElevation];
  const float ratio = angle / half;
  const float limb = 1.0f - 0.6f * (1.0f - std::sqrt(std::max(0.0f, 1.0f - ratio * ratio)));
  if (style != Style::kNishita) {
    // 5.x: the disc over the sky down to a little below the horizon (the Earth's edge
    // seen from the altitude), its colour from its lowest to its highest point.
    if (!(elevation > t[kDiscLowest])) return xyz_to_rec709(sky);
    const float y = (elevation - sun_elevation) / diameter + 0.5f;
    return xyz_to_rec709(sky + lerp(bottom, top, y) * (limb * t[kSunIntensity]));
  }
  // 3.x/4.x: the disc instead of the sky; a disc the horizon cuts spans its visible part.
  if (sun_elevation + half <= 0.0f) return Vec3(0.0f);
  const float y = sun_elevation - half > 0.0f ? (elevation - sun_elevation) / diameter + 0.5f
                                              : elevation / (sun_elevation + half);
  return xyz_to_rec709(lerp(bottom, top, y) * (t[kSunIntensity] * limb));
}

Vec3 finite_or_black(Vec3 c) {
  return is_finite(c) ? glm::max(c, Vec3(0.0f)) : Vec3(0.0f);
}

}  // namespace

Vec3 xyz_to_rec709(Vec3 xyz) {
  const Vec3 rgb(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z,
                 -0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z,
                 0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z);
  return glm::max(rgb, Vec3(0.0f));
}

float preetham_zenith_luminance(float theta_sun, float turbidity) {
  const float chi = (4.0f / 9.0f - turbidity / 120.0f) * (kPi - 2.0f * theta_sun);
  return (4.0453f * turbidity - 4.9710f) * std::tan(chi) - 0.2155f * turbidity + 2.4192f;
}

std::vector<float> preetham_table(Vec3 sun, float turbidity) {
  const float t = turbidity;
  const float theta = zenith_angle(sun);
  std::vector<float> table(kPreethamSize);
  table[kSunTheta] = theta;
  table[kSunPhi] = azimuth(sun);
  // Cycles scales the zenith luminance (kcd/m^2) by 0.06.
  table[kZenith] = preetham_zenith_luminance(theta, t) * 0.06f;
  table[kZenith + 1] = zenith_chromaticity({{{0.00166f, -0.00375f, 0.00209f, 0.0f},
                                             {-0.02903f, 0.06377f, -0.03202f, 0.00394f},
                                             {0.11693f, -0.21196f, 0.06052f, 0.25886f}}},
                                           theta, t);
  table[kZenith + 2] = zenith_chromaticity({{{0.00275f, -0.00610f, 0.00317f, 0.0f},
                                             {-0.04214f, 0.08970f, -0.04153f, 0.00516f},
                                             {0.15346f, -0.26756f, 0.06670f, 0.26688f}}},
                                           theta, t);
  // The Perez coefficients A..E of Y, x and y, linear in turbidity (Preetham's appendix).
  constexpr std::array<std::array<float, 2>, 15> kCoefficients = {{
      {0.1787f, -1.4630f},
      {-0.3554f, 0.4275f},
      {-0.0227f, 5.3251f},
      {0.1206f, -2.5771f},
      {-0.0670f, 0.3703f},
      {-0.0193f, -0.2592f},
      {-0.0665f, 0.0008f},
      {-0.0004f, 0.2125f},
      {-0.0641f, -0.8989f},
      {-0.0033f, 0.0452f},
      {-0.0167f, -0.2608f},
      {-0.0950f, 0.0092f},
      {-0.0079f, 0.2102f},
      {-0.0441f, -1.6537f},
      {-0.0109f, 0.0529f},
  }};
  for (size_t i = 0; i < kCoefficients.size(); ++i) {
    table[kPerez + i] = kCoefficients[i][0] * t + kCoefficients[i][1];
  }
  // Each zenith value is the distribution's there: divide by its Perez function.
  for (size_t c = 0; c < 3; ++c) table[kZenith + c] /= perez(&table[kPerez + 5 * c], 0.0f, theta);
  return table;
}

std::vector<float> hosek_wilkie_table(Vec3 sun, float turbidity, float ground_albedo) {
  std::vector<float> table(kHosekSize);
  const float theta = std::min(zenith_angle(sun), kHalfPi);
  table[kHosekSunTheta] = theta;
  table[kHosekSunPhi] = azimuth(sun);
  const double t =
      std::isnan(turbidity) ? 1.0 : std::clamp(static_cast<double>(turbidity), 1.0, 10.0);
  const double albedo =
      std::isnan(ground_albedo) ? 0.0 : std::clamp(static_cast<double>(ground_albedo), 0.0, 1.0);
  // The Bezier's parameter: the cube root of the solar elevation over pi/2, the
  // elevation in float as Cycles takes it (0 for the sun at or below the horizon).
  const float elevation = kHalfPi - theta;
  const double s = std::cbrt(static_cast<double>(elevation) / (std::numbers::pi / 2.0));
  // Cycles' scale of the model's radiance.
  constexpr double kScale = 2.0 * std::numbers::pi / 683.0;
  for (size_t c = 0; c < 3; ++c) {
    float* channel = &table[kHosekChannels + c * kHosekChannel];
    cook(hosek_wilkie_data::kParameters.data(), kHosekParameters, c, t, albedo, s, channel);
    cook(hosek_wilkie_data::kRadiances.data(), 1, c, t, albedo, s, channel + kHosekParameters);
    channel[kHosekParameters] = static_cast<float>(channel[kHosekParameters] * kScale);
  }
  return table;
}

Vec3 sun_direction(float elevation, float rotation) {
  return {std::cos(elevation) * std::sin(rotation), std::cos(elevation) * std::cos(rotation),
          std::sin(elevation)};
}

std::vector<float> scattering_table(const ScatteringParams& p, uint32_t columns, uint32_t rows) {
  columns = std::max(columns, 1u);
  rows = std::max(rows, 1u);
  const bool multiple = p.style == Style::kMultipleScattering;
  const uint32_t stored_rows = multiple ? 2 * rows : rows;
  std::vector<float> table(kScatteringHeader + 3 * static_cast<size_t>(columns) * stored_rows);
  const Vec3 sun = sun_direction(p.sun_elevation, p.sun_rotation);
  for (size_t i = 0; i < 3; ++i) table[kSun + i] = sun[i];
  table[kSunElevation] = p.sun_elevation;
  table[kSunDiameter] = p.sun_disc ? p.sun_size : -1.0f;
  table[kSunIntensity] = p.sun_intensity;
  table[kStyle] = static_cast<float>(p.style);
  table[kColumns] = static_cast<float>(columns);
  table[kRows] = static_cast<float>(rows);
  // 5.x draws the disc down to the Earth's edge seen from the altitude (as its multiple-
  // scattering model sizes the Earth, and the altitude unclamped).
  constexpr double kDiscEarthRadius = kMsEarthRadius * 1e3;
  table[kDiscLowest] = static_cast<float>(
      -(std::numbers::pi / 2.0 -
        std::asin(kDiscEarthRadius / (kDiscEarthRadius + static_cast<double>(p.altitude)))));
  const float half = p.sun_size / 2.0f;
  const float solid_angle = 2.0f * kPi * (1.0f - std::cos(half));
  const auto set_disc = [&](Vec3 bottom, Vec3 top) {
    for (size_t i = 0; i < 3; ++i) table[kDiscBottom + i] = bottom[i], table[kDiscTop + i] = top[i];
  };
  const Vec3 scale(p.air_density, p.dust_density, p.ozone_density);
  std::function<Vec3(uint32_t, uint32_t)> bake;
  MultipleScattering ms(scale);
  const DVec3 towards_sun(std::cos(p.sun_elevation), 0.0, std::sin(p.sun_elevation));
  const Atmosphere atmosphere{
      DVec3(0.0, 0.0, kEarthRadius + std::clamp(p.altitude, 1.0f, 59999.0f)), scale};
  if (multiple) {
    const float altitude = std::clamp(p.altitude, 1.0f, 99999.0f) / 1000.0f;  // km
    const float height = altitude / kMsAtmosphereHeight;
    // The disc's colour at its lowest and highest points, through the atmosphere
    // without the horizon's cut.
    if (p.sun_disc && solid_angle > 0.0f) {
      const auto disc = [&](float elevation) {
        return ms_to_xyz(kMsSunIrradiance * ms.transmittance(std::sin(elevation), height) /
                         solid_angle);
      };
      set_disc(disc(p.sun_elevation - half), disc(p.sun_elevation + half));
    }
    ms.tabulate();
    // Texel (c, r) at its centre: azimuth 2 pi (c + 0.5) / width with the sun at pi.
    const Vec3 towards(ms_sun(std::sin(p.sun_elevation)));
    const Vec3 origin(0.0f, 0.0f, kMsEarthRadius + altitude);
    bake = [&, towards, origin](uint32_t r, uint32_t c) {
      const auto elevation = static_cast<float>(row_elevation(p.style, r, rows));
      const float az = kPi * (static_cast<float>(c) + 0.5f) / static_cast<float>(columns);
      const Vec3 view(std::cos(elevation) * std::cos(az), std::cos(elevation) * std::sin(az),
                      std::sin(elevation));
      const float ground = ms_to_sphere(origin, view, kMsEarthRadius);
      const float length = ground < 0.0f ? ms_to_sphere(origin, view, kMsAtmosphereRadius) : ground;
      return ms_to_xyz(ms.inscattered(towards, origin, view, length));
    };
  } else {
    // The disc's colour at its lowest and highest points (each at the horizon at least).
    if (p.sun_disc && p.sun_elevation + half > 0.0f && solid_angle > 0.0f) {
      set_disc(sun_radiance(atmosphere, std::max(p.sun_elevation - half, 0.0f), solid_angle),
               sun_radiance(atmosphere, p.sun_elevation + half, solid_angle));
    }
    // The sun towards +X; column c at the azimuth Cycles bakes its texel c at,
    // pi (1 - c / columns) from the sun (half a texel further than the texel's centre,
    // which its kernel reads).
    bake = [&](uint32_t r, uint32_t c) {
      const double elevation = row_elevation(p.style, r, rows);
      const double relative = std::numbers::pi * (1.0 - static_cast<double>(c) / columns);
      const DVec3 view(std::cos(elevation) * std::cos(relative),
                       std::cos(elevation) * std::sin(relative), std::sin(elevation));
      return inscattered(atmosphere, view, towards_sun);
    };
  }
  const auto fill = [&](uint32_t first, uint32_t step) {
    for (uint32_t r = first; r < stored_rows; r += step) {
      for (uint32_t c = 0; c < columns; ++c) {
        const Vec3 xyz = bake(r, c);
        float* out = &table[kScatteringHeader + 3 * (static_cast<size_t>(r) * columns + c)];
        out[0] = xyz.x, out[1] = xyz.y, out[2] = xyz.z;
      }
    }
  };
  const auto threads = std::clamp(std::thread::hardware_concurrency(), 1u, 16u);
  std::vector<std::thread> pool;
  for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(fill, t, threads);
  fill(0, threads);
  for (std::thread& t : pool) t.join();
  return table;
}

size_t table_size(Model model, const float* table, size_t available) {
  if (model == Model::kPreetham) return available >= kPreethamSize ? kPreethamSize : 0;
  if (model == Model::kHosekWilkie) return available >= kHosekSize ? kHosekSize : 0;
  if (model != Model::kSingleScattering || available < kScatteringHeader) return 0;
  const float columns = table[kColumns];
  const float rows = table[kRows];
  const float style = table[kStyle];
  if (!(columns >= 1.0f && rows >= 1.0f && columns <= 65536.0f && rows <= 65536.0f) ||
      columns != std::floor(columns) || rows != std::floor(rows) ||
      !(style == 0.0f || style == 1.0f || style == 2.0f)) {
    return 0;
  }
  const size_t stored = static_cast<size_t>(rows) * (style == 2.0f ? 2 : 1);
  const size_t size = kScatteringHeader + 3 * static_cast<size_t>(columns) * stored;
  return size <= available ? size : 0;
}

Vec3 radiance(Model model, const float* table, Vec3 direction) {
  if (!is_finite(direction)) return Vec3(0.0f);
  switch (model) {
    case Model::kPreetham:
      return finite_or_black(preetham(table, direction));
    case Model::kHosekWilkie:
      return finite_or_black(hosek_wilkie(table, direction));
    case Model::kSingleScattering:
      break;
  }
  return finite_or_black(single_scattering(table, direction));
}

}  // namespace whitted::sky
