#include "radiosity/punctual_lights.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/strings.h"
#include "radiosity/kernel_inputs.h"
#include "raycast/ray_caster.h"
#include "shared/rng.h"
#include "spectral/fluorescence.h"

namespace daisy {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kRegions = 4;  // visibility regions per patch: its midpoint subdivision
constexpr int kAzimuthSteps = 16;  // per edge, in the falloff's quadrature around the foot point

// A point of triangle t, uniform in area, from a hash of (patch, region): where a region's
// shadow segment starts. Its centroid would fall into the same gaps of a regular floor for
// every patch: 0.5 m tiles 1 cm apart over a grout sheet 5 mm below, the sheet's patches cut
// at whole metres, put their region centroids in the gaps, and the sheet got 79% of the light
// it gets without the tiles, where the gaps pass 4%.
Vec3d jitteredPoint(const Triangle3d& t, uint32_t patch, int region) {
    const uint32_t seed = shared::pcgHash(patch * uint32_t(kRegions) + uint32_t(region));
    double u = shared::hashToUnitFloat(0, seed), v = shared::hashToUnitFloat(1, seed);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    return t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
}

// The midpoint subdivision of t (same orientation): the three corner triangles, then the middle
// one: the patch's visibility regions, each seen through one shadow segment.
std::array<Triangle3d, 4> midpointChildren(const Triangle3d& t) {
    const Vec3d ab = (t[0] + t[1]) * 0.5, bc = (t[1] + t[2]) * 0.5, ca = (t[2] + t[0]) * 0.5;
    return {{{t[0], ab, ca}, {ab, t[1], bc}, {ca, bc, t[2]}, {ab, bc, ca}}};
}

Vec3d centroidOf(const Triangle3d& t) {
    return (t[0] + t[1] + t[2]) / 3.0;
}

double longestEdge(const Triangle3d& t) {
    return std::max({length(t[1] - t[0]), length(t[2] - t[1]), length(t[0] - t[2])});
}

// Edge p -> q of a triangle seen from the foot point f of a light at height h over its plane:
// the signed distance from f to the edge's line (positive on the inner side of a
// counter-clockwise edge) and the positions sP < sQ of p and q along the line from f's
// perpendicular foot on it. Computed from the edge's midpoint and direction, so the edge read
// q -> p by the neighbour across it gives exactly the negated values.
struct EdgeFromFoot {
    double side = 0;  // signed distance, scene units
    double sP = 0, sQ = 0;  // scene units
    Vec3d toward;  // unit, in the plane: from f perpendicularly towards the line
    Vec3d along;  // unit, p -> q
};

EdgeFromFoot edgeFromFoot(const Vec3d& p, const Vec3d& q, const Vec3d& foot, const Vec3d& n) {
    EdgeFromFoot e;
    const Vec3d edge = q - p;
    const double edgeLength = length(edge);
    if (!(edgeLength > 0)) return e;
    e.along = edge / edgeLength;
    const Vec3d inner = cross(n, e.along);  // in the plane, towards the inside
    e.side = dot(foot - (p + q) * 0.5, inner);
    e.toward = e.side >= 0 ? -inner : inner;
    e.sP = dot(p - foot, e.along);
    e.sQ = dot(q - foot, e.along);
    return e;
}

// The solid angle of the planar triangle t from a point at height h > 0 over its plane, as the
// signed sum over its edges of the wedge between the foot point and the edge: at distance rho,
// with the edge from sP to sQ along its line, integral over the azimuth psi = atan(s / rho) of
// (1 - cos theta) = [atan2(s, rho) - atan2(h s, rho sqrt(h^2 + rho^2 + s^2))] from sP to sQ (the
// second term is asin(h sin psi / sqrt(h^2 + rho^2)) without its rounding near +-1). Accurate
// to rounding in absolute terms however low the light; as h -> 0 it is the angle t covers
// around the foot (2 pi inside, pi on an edge), and two triangles sharing an edge cancel its
// terms exactly.
double solidAngleFromFoot(const Triangle3d& t, const Vec3d& foot, const Vec3d& n, double h) {
    double sum = 0;
    for (int k = 0; k < 3; ++k) {
        const EdgeFromFoot e = edgeFromFoot(t[k], t[(k + 1) % 3], foot, n);
        const double rho = std::abs(e.side);
        if (!(rho > 0)) continue;  // the foot on the edge's line: no wedge
        const auto term = [&](double s) {
            // In units of the largest length, so that products of lengths near 1e-300 do not
            // underflow.
            const double unit = std::max({h, rho, std::abs(s)});
            const double hu = h / unit, ru = rho / unit, su = s / unit;
            return std::atan2(su, ru) -
                std::atan2(hu * su, ru * std::sqrt(hu * hu + ru * ru + su * su));
        };
        const double wedge = term(e.sQ) - term(e.sP);
        sum += e.side > 0 ? wedge : -wedge;
    }
    return sum;
}

// Gauss-Legendre nodes and weights on [-1, 1], 4 points (exact to degree 7).
constexpr std::array<double, 4> kGaussNodes = {-0.8611363115940526, -0.3399810435848563,
                                               0.3399810435848563, 0.8611363115940526};
constexpr std::array<double, 4> kGaussWeights = {0.3478548451374538, 0.6521451548625461,
                                                 0.6521451548625461, 0.3478548451374538};

// The falloff's mean over the directions from the light (at height h over t's plane, foot point
// `foot`) to t, weighted by solid angle: per edge, the wedge from the foot (signed as in
// solidAngleFromFoot) in kAzimuthSteps azimuths psi (midpoint rule), and along each azimuth the
// polar angle from the foot to the edge split where the spot cone's edges and the range cross it
// (there the falloff has kinks), each piece by 4-point Gauss-Legendre in cos(theta).
double meanFalloffAroundFoot(const PunctualLight& light, const Triangle3d& t, const Vec3d& foot,
                             const Vec3d& n, double h) {
    const bool spot = light.type == PunctualLight::Type::Spot;
    const std::array<double, 2> coneCosines = {std::cos(light.outerConeRad),
                                               std::cos(light.innerConeRad)};
    double weights = 0, weighted = 0;
    std::array<double, 7> cuts{};  // 0, the edge, two per cone edge, the range
    for (int k = 0; k < 3; ++k) {
        const EdgeFromFoot e = edgeFromFoot(t[k], t[(k + 1) % 3], foot, n);
        const double rho = std::abs(e.side);
        if (!(rho > 0)) continue;
        const double sign = e.side > 0 ? 1.0 : -1.0;
        const double psiP = std::atan2(e.sP, rho);
        const double dPsi = (std::atan2(e.sQ, rho) - psiP) / kAzimuthSteps;
        for (int a = 0; a < kAzimuthSteps; ++a) {
            const double psi = psiP + (a + 0.5) * dPsi;
            const Vec3d inPlane = e.toward * std::cos(psi) + e.along * std::sin(psi);
            const double thetaEdge = std::atan2(rho / std::cos(psi), h);
            cuts[0] = 0;
            cuts[1] = thetaEdge;
            std::size_t cutCount = 2;
            const auto cut = [&](double theta) {  // inserted in order
                if (!(theta > 0 && theta < thetaEdge) || cutCount == cuts.size()) return;
                std::size_t at = cutCount++;
                for (; cuts[at - 1] > theta; --at)
                    cuts[at] = cuts[at - 1];
                cuts[at] = theta;
            };
            if (spot) {
                // The cosine from the axis along this azimuth: sin(theta) x + cos(theta) y =
                // r cos(theta - theta0).
                const double x = dot(inPlane, light.direction), y = -dot(n, light.direction);
                const double r = std::hypot(x, y), theta0 = std::atan2(x, y);
                for (const double c : coneCosines) {
                    if (std::abs(c) >= r) continue;
                    const double half = std::acos(c / r);
                    cut(theta0 - half);
                    cut(theta0 + half);
                }
            }
            if (light.range > h) cut(std::acos(h / light.range));
            for (std::size_t piece = 0; piece + 1 < cutCount; ++piece) {
                const double muHigh = std::cos(cuts[piece]), muLow = std::cos(cuts[piece + 1]);
                const double halfWidth = (muHigh - muLow) / 2, middle = (muHigh + muLow) / 2;
                for (std::size_t g = 0; g < kGaussNodes.size(); ++g) {
                    const double mu = middle + halfWidth * kGaussNodes[g];
                    const double w = sign * kGaussWeights[g] * halfWidth * dPsi;
                    const Vec3d direction =
                        inPlane * std::sqrt(std::max(0.0, 1 - mu * mu)) - n * mu;
                    weights += w;
                    weighted += w * punctualFalloff(light, h / mu, dot(light.direction, direction));
                }
            }
        }
    }
    return weights > 0 ? std::clamp(weighted / weights, 0.0, 1.0) : 0.0;
}

// The falloff's mean over the directions from the light to t, weighted by solid angle: around
// the foot point when the light is closer to t than t's size (where directions spread over up
// to a hemisphere however small t is), else over the 16 triangles of two midpoint
// subdivisions, each weighted by its exact solid angle.
double meanFalloff(const PunctualLight& light, const Triangle3d& t, const Vec3d& n, double h) {
    const Vec3d foot = light.position - n * h;
    const double longest = longestEdge(t);
    if (h < longest && length(foot - centroidOf(t)) < 2 * longest)
        return meanFalloffAroundFoot(light, t, foot, n, h);
    std::array<Triangle3d, 16> parts;
    std::array<double, 16> falloffs;
    bool uniform = true;
    std::size_t count = 0;
    for (const Triangle3d& child : midpointChildren(t)) {
        for (const Triangle3d& part : midpointChildren(child)) {
            const Vec3d toPart = centroidOf(part) - light.position;
            const double distance = length(toPart);
            parts[count] = part;
            falloffs[count] =
                punctualFalloff(light, distance, dot(light.direction, toPart / distance));
            uniform = uniform && falloffs[count] == falloffs[0];
            ++count;
        }
    }
    if (uniform) return falloffs[0];  // all inside the cone or all outside: no weights needed
    double weights = 0, weighted = 0;
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const double omega = frontSolidAngle(light.position, parts[k], n);
        weights += omega;
        weighted += omega * falloffs[k];
    }
    return weights > 0 ? weighted / weights : 0;
}

bool hasFalloff(const PunctualLight& light) {
    return light.range > 0 || light.type == PunctualLight::Type::Spot;
}

}  // namespace

double punctualTriangleFlux(const PunctualLight& light, const Triangle3d& t, const Vec3d& n) {
    const double omega = frontSolidAngle(light.position, t, n);
    if (!(omega > 0) || !hasFalloff(light)) return omega;
    const double h = dot(n, light.position - centroidOf(t));
    return omega * meanFalloff(light, t, n, h);
}

double frontSolidAngle(const Vec3d& from, const Triangle3d& t, const Vec3d& n) {
    const Vec3d centroid = centroidOf(t);
    const double h = dot(n, from - centroid);
    if (!(h > 0) || !std::isfinite(h)) return 0;
    const Vec3d foot = from - n * h;
    const double longest = longestEdge(t);
    double omega;
    if (h < longest && length(foot - centroid) < 2 * longest) {
        omega = solidAngleFromFoot(t, foot, n, h);
    } else {
        // Van Oosterom & Strackee 1983: tan(omega / 2) = [u0 u1 u2] / (1 + u0.u1 + u1.u2 +
        // u2.u0) for the unit vectors u towards the corners; the triple product is negative
        // for a triangle facing the point.
        std::array<Vec3d, 3> u;
        for (int k = 0; k < 3; ++k) {
            const Vec3d d = t[k] - from;
            const double r = length(d);
            if (!(r > 0) || !std::isfinite(r)) return 0;
            u[k] = d / r;
        }
        const double det = dot(u[0], cross(u[1], u[2]));
        const double denominator = 1 + dot(u[0], u[1]) + dot(u[1], u[2]) + dot(u[2], u[0]);
        omega = -2 * std::atan2(det, denominator);
    }
    return std::clamp(omega, 0.0, 2 * kPi);
}

double punctualFalloff(const PunctualLight& light, double distance, double cosFromAxis) {
    double falloff = 1;
    if (light.range > 0) {
        // KHR_lights_punctual: clamp(1 - (d / range)^4, 0, 1) windows the inverse square.
        const double ratio = distance / light.range;
        falloff = std::clamp(1 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    }
    if (light.type == PunctualLight::Type::Spot) {
        const double cosOuter = std::cos(light.outerConeRad);
        const double cosInner = std::cos(light.innerConeRad);
        const double scale = 1 / std::max(0.001, cosInner - cosOuter);
        const double t = std::clamp((cosFromAxis - cosOuter) * scale, 0.0, 1.0);
        falloff *= t * t;
    }
    return falloff;
}

double punctualPointFactor(const PunctualLight& light, const Vec3d& x, const Vec3d& n, double far,
                           Vec3d& shadowEnd) {
    double g;
    if (light.type == PunctualLight::Type::Directional) {
        g = -dot(n, light.direction);
        shadowEnd = x - light.direction * far;
    } else {
        const Vec3d d = light.position - x;
        const double r = length(d);
        g = dot(n, d) / (r * r * r) * punctualFalloff(light, r, -dot(light.direction, d) / r);
        shadowEnd = light.position;
    }
    return g > 0 && std::isfinite(g) ? g : 0.0;
}

double leavingLength(const PatchMesh& patches) {
    Bounds3d bounds;
    for (const Vec3d& p : patches.positions)
        bounds.extend(p);
    return 4 * std::max(bounds.diagonal(), 1e-9);
}

Expected<LightGeometry> punctualLightGeometry(const PatchMesh& patches,
                                              const std::vector<PunctualLight>& lights) {
    LightGeometry geometry;
    geometry.lightCount = lights.size();
    const std::size_t n = patches.patchCount(), count = lights.size();
    geometry.factors.assign(n * count, 0);
    if (n == 0 || count == 0) return geometry;
    auto caster = makeRayCaster(patches);
    if (!caster) return withContext(caster.error(), "lights");
    const double far = leavingLength(patches);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const auto& range) {
        SegmentArrays segments;
        std::vector<uint8_t> blocked;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Vec3d& normal = patches.normals[i];
            const double area = patches.areas[i];
            if (!(area > 0)) continue;
            const auto& c = patches.patches[i];
            const Triangle3d corners{patches.positions[c[0]], patches.positions[c[1]],
                                     patches.positions[c[2]]};
            const auto regions = midpointChildren(corners);
            double scale = 0;  // the largest coordinate magnitude of the patch
            for (const Vec3d& p : corners)
                scale = std::max({scale, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
            const double clearance = double(kEndClearanceRelative) * scale;
            for (std::size_t l = 0; l < count; ++l) {
                const PunctualLight& light = lights[l];
                const bool directional = light.type == PunctualLight::Type::Directional;
                // Per region: its share of g (before visibility).
                std::array<double, kRegions> share{};
                double total = 0;
                if (directional) {
                    const double cosine = dot(normal, -light.direction);
                    if (!(cosine > 0)) continue;  // the light is behind the patch
                    share.fill(cosine / kRegions);
                    total = cosine;
                } else {
                    for (int k = 0; k < kRegions; ++k) {
                        share[k] = punctualTriangleFlux(light, regions[k], normal) / area;
                        total += share[k];
                    }
                    if (!(total > 0)) continue;
                }
                segments.resize(kRegions);
                for (int k = 0; k < kRegions; ++k) {
                    const Vec3d p = jitteredPoint(regions[k], uint32_t(i), k);
                    const Vec3d end = directional ? p - light.direction * far : light.position;
                    // Start where the segment is `clearance` above the patch's plane (as the
                    // view factors' segments do): the patch and those coplanar with it never
                    // block it; a light closer to the plane than that leaves it empty (open).
                    const double rise = dot(normal, end - p);
                    const Vec3d start = rise > clearance ? p + (end - p) * (clearance / rise) : end;
                    segments.set(k, float(start.x), float(start.y), float(start.z), float(end.x),
                                 float(end.y), float(end.z));
                }
                blocked.assign(kRegions, 0);
                (*caster)->occluded(segments, blocked);
                double factor = 0;
                for (int k = 0; k < kRegions; ++k)
                    factor += blocked[k] == 0 ? share[k] : 0.0;
                geometry.factors[i * count + l] = factor;
            }
        }
    });
    return geometry;
}

Expected<std::vector<std::vector<double>>> punctualLightSpectra(
    const std::vector<PunctualLight>& lights, const WavelengthSet& set) {
    std::vector<std::vector<double>> spectra;
    for (const PunctualLight& light : lights) {
        const Rgb rgb{light.color[0] * light.intensity, light.color[1] * light.intensity,
                      light.color[2] * light.intensity};
        std::optional<SpectrumSpec> spectral = light.spectrum;
        if (spectral) spectral->scale *= light.intensity;
        auto spectrum = materialEmission(set, spectral, rgb, concat("light '", light.name, "'"));
        if (!spectrum) return spectrum.error();
        spectra.push_back(std::move(*spectrum));
    }
    return spectra;
}

Expected<void> addDirectLight(RadiositySystem& system, const LightGeometry& geometry,
                              const std::vector<PunctualLight>& lights, const WavelengthSet& set) {
    const std::size_t m = system.wavelengthCount, count = lights.size();
    if (count == 0) return {};
    auto spectra = punctualLightSpectra(lights, set);
    if (!spectra) return spectra.error();
    std::vector<double> irradiance(m);
    system.punctualEmission.assign(system.emission.size(), 0.0);
    for (uint32_t i = 0; i < system.patchCount; ++i) {
        std::fill(irradiance.begin(), irradiance.end(), 0.0);
        bool lit = false;
        for (std::size_t l = 0; l < count; ++l) {
            const double g = geometry.factors[std::size_t(i) * count + l];
            if (g <= 0) continue;
            lit = true;
            for (std::size_t k = 0; k < m; ++k)
                irradiance[k] += g * (*spectra)[l][k];
        }
        if (!lit) continue;
        double* e = system.emission.data() + std::size_t(i) * m;
        double* reflected = system.punctualEmission.data() + std::size_t(i) * m;
        applyOperator(system.operators[system.patchOperator[i]], irradiance.data(), reflected);
        for (std::size_t k = 0; k < m; ++k)
            e[k] += reflected[k];
    }
    return {};
}

}  // namespace daisy
