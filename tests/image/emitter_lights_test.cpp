// The final gather's merged emitter faces (image/emitter_lights.h): a tessellated flat convex
// face becomes a fan over its outline with the same area and, from any receiver point, the same
// exact factor as its triangles (additivity of Lambert's contour formula); anything that is not
// one flat convex face of one emission is kept as it is. A light hidden from a patch has an
// exact factor of 0 from every point of it, and lights that graze the patch are not hidden.
#include "image/emitter_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "shared/formfactor.h"
#include "shared/rng.h"

namespace daisy {
namespace {

// An n x n grid of the unit square in the plane z = height, facing -z (counter-clockwise seen
// from below), 2 n^2 triangles.
void addGrid(TriangleMesh& mesh, int n, double height) {
    const uint32_t base = uint32_t(mesh.positions.size());
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i)
            mesh.positions.push_back({double(i) / n, double(j) / n, height});
    }
    const auto at = [&](int i, int j) { return base + uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    }
}

std::vector<uint32_t> allTriangles(const TriangleMesh& mesh) {
    std::vector<uint32_t> t(mesh.triangleCount());
    for (uint32_t i = 0; i < t.size(); ++i)
        t[i] = i;
    return t;
}

shared::PatchGeometry geometryOf(const std::array<Vec3d, 3>& c) {
    const auto v = [](const Vec3d& p) { return shared::vec3{float(p.x), float(p.y), float(p.z)}; };
    return shared::makePatchGeometry(v(c[0]), v(c[1]), v(c[2]));
}

double areaOf(const std::vector<LightTriangle>& lights) {
    double area = 0;
    for (const LightTriangle& l : lights)
        area += triangleArea(l.corners[0], l.corners[1], l.corners[2]);
    return area;
}

TEST(EmitterLights, TessellatedSquareBecomesTwoTrianglesWithTheSameFactors) {
    TriangleMesh mesh;
    addGrid(mesh, 4, 1.0);
    const std::vector<uint32_t> triangles = allTriangles(mesh);
    const std::vector<uint32_t> classes(triangles.size(), 0);
    const std::vector<LightTriangle> lights = mergeEmitterFaces(mesh, triangles, classes);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_NEAR(areaOf(lights), 1.0, 1e-12);
    for (const LightTriangle& l : lights) {
        EXPECT_LT(areaVector2(l.corners[0], l.corners[1], l.corners[2]).z, 0);  // still faces -z
        EXPECT_LT(l.sourceTriangle, triangles.size());
    }
    // Receivers below the square, facing up, one tilted so the square straddles its plane.
    const shared::vec3 points[] = {{0.5f, 0.5f, 0.0f}, {0.1f, 0.8f, 0.6f}, {-0.7f, 0.3f, 0.2f}};
    const shared::vec3 normals[] = {{0, 0, 1}, {0, 0, 1}, {0.6f, 0, 0.8f}};
    for (int r = 0; r < 3; ++r) {
        double original = 0, merged = 0;
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            original += shared::pointToTriangleFactor(
                points[r], normals[r],
                geometryOf({mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)}));
        }
        for (const LightTriangle& l : lights)
            merged += shared::pointToTriangleFactor(points[r], normals[r], geometryOf(l.corners));
        EXPECT_GT(original, 0.01) << "receiver " << r;
        EXPECT_NEAR(merged, original, 1e-5) << "receiver " << r;
    }
    // Closed form at the centre, 1 below the unit square: four times the factor from a corner
    // point to a parallel 0.5 x 0.5 rectangle at height 1, (1/2pi) (X / sqrt(1 + X^2)
    // atan(Y / sqrt(1 + X^2)) + (X <-> Y)) with X = Y = 0.5 (Howell's catalog, config. B-3).
    const double a = 0.5, s = a / std::sqrt(1 + a * a);
    double merged = 0;
    for (const LightTriangle& l : lights)
        merged += shared::pointToTriangleFactor(points[0], normals[0], geometryOf(l.corners));
    EXPECT_NEAR(merged, 4.0 / (2 * 3.14159265358979323846) * 2 * s * std::atan(s), 1e-5);
}

// A Blender-style export: a 36 x 36 grid whose inner vertices sit up to 1e-6 off the plane
// (tools/make_formfactor_family.py's blender_cornell ceiling) is still one light of 2 triangles
// with the grid's area; the 2,592 triangles kept apart made its final gather 15x slower.
TEST(EmitterLights, AFaceFlatToRoundingOfItsExportIsMerged) {
    TriangleMesh mesh;
    addGrid(mesh, 36, 1.0);
    uint32_t state = 7;
    for (Vec3d& p : mesh.positions) {
        state = state * 1664525u + 1013904223u;
        if (p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1)
            p.z += 1e-6 * (double(state >> 8) / (1 << 24) - 0.5) * 2;
    }
    const std::vector<uint32_t> triangles = allTriangles(mesh);
    const std::vector<uint32_t> classes(triangles.size(), 0);
    const std::vector<LightTriangle> lights = mergeEmitterFaces(mesh, triangles, classes);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_NEAR(areaOf(lights), 1.0, 1e-9);
}

TEST(EmitterLights, DifferentEmissionsPlanesAndConcaveOutlinesAreKept) {
    TriangleMesh mesh;
    addGrid(mesh, 2, 1.0);  // 8 triangles
    const std::vector<uint32_t> triangles = allTriangles(mesh);
    // Two emission classes by column: each half (a 0.5 x 1 rectangle of 4 triangles) merges
    // into 2 triangles on its own.
    std::vector<uint32_t> classes(triangles.size());
    for (uint32_t t = 0; t < triangles.size(); ++t)
        classes[t] = (t / 2) % 2;
    std::vector<LightTriangle> lights = mergeEmitterFaces(mesh, triangles, classes);
    EXPECT_EQ(lights.size(), 4u);
    EXPECT_NEAR(areaOf(lights), 1.0, 1e-12);
    for (std::size_t l = 0; l < lights.size(); ++l)
        EXPECT_EQ(classes[lights[l].sourceTriangle], l < 2 ? 0u : 1u) << "light " << l;
    // An L of three cells (one corner cell left out, concave): kept as its 6 triangles.
    const std::vector<uint32_t> lShape{0, 1, 2, 3, 4, 5};
    const std::vector<uint32_t> oneClass(lShape.size(), 0);
    lights = mergeEmitterFaces(mesh, lShape, oneClass);
    EXPECT_EQ(lights.size(), 6u);
    // The grid folded: a second grid at another height does not join the first, and a single
    // quad (two triangles) is kept as it is.
    TriangleMesh two;
    addGrid(two, 1, 1.0);
    addGrid(two, 3, 2.0);
    const std::vector<uint32_t> all = allTriangles(two);
    lights = mergeEmitterFaces(two, all, std::vector<uint32_t>(all.size(), 0));
    ASSERT_EQ(lights.size(), 4u);
    EXPECT_EQ(lights[0].corners[1].y, 1.0);  // the quad's own first triangle, unchanged
    EXPECT_EQ(lights[0].sourceTriangle, 0u);
    EXPECT_EQ(lights[1].sourceTriangle, 1u);
    EXPECT_NEAR(areaOf(lights), 2.0, 1e-12);
}

shared::vec3 randomPoint(uint32_t& state, float scale) {
    const auto u = [&]() {
        state = shared::pcgHash(state);
        return shared::uintToUnitFloat(state) * 2.0f - 1.0f;
    };
    const float x = u(), y = u(), z = u();
    return shared::vec3{x, y, z} * scale;
}

// Points of the receiver where the factor is evaluated: its corners, edge midpoints, centroid
// and random barycentric points, each rounded to float as the gather's points are.
std::vector<shared::vec3> pointsOn(const shared::PatchGeometry& t, uint32_t& state) {
    std::vector<shared::vec3> points = {t.a,
                                        t.b,
                                        t.c,
                                        (t.a + t.b) * 0.5f,
                                        (t.b + t.c) * 0.5f,
                                        (t.c + t.a) * 0.5f,
                                        (t.a + t.b + t.c) * (1.0f / 3.0f)};
    for (int k = 0; k < 24; ++k) {
        state = shared::pcgHash(state);
        double u = shared::uintToUnitFloat(state);
        state = shared::pcgHash(state);
        double v = shared::uintToUnitFloat(state);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        const auto at = [&](float a, float b, float c) {
            return float((1 - u - v) * double(a) + u * double(b) + v * double(c));
        };
        points.push_back(
            {at(t.a.x, t.b.x, t.c.x), at(t.a.y, t.b.y, t.c.y), at(t.a.z, t.b.z, t.c.z)});
    }
    return points;
}

TEST(EmitterLights, AHiddenLightHasAZeroFactorFromEveryPointOfThePatch) {
    uint32_t state = 12345;
    int hidden = 0, seen = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        // Receivers and lights of sizes 1e-3..1 around an offset up to 1e3 from the origin; half
        // of the lights moved just under the receiver's plane, by 1e-6..1e-2 of its size, across
        // the predicate's margin (about 4e-5 of the distances).
        const float scale = std::pow(10.0f, -3.0f * float(trial % 4) / 3.0f);
        const shared::vec3 offset = randomPoint(state, trial % 3 == 0 ? 1000.0f : 1.0f);
        const shared::PatchGeometry receiver = shared::makePatchGeometry(
            offset + randomPoint(state, scale), offset + randomPoint(state, scale),
            offset + randomPoint(state, scale));
        shared::vec3 c[3] = {offset + randomPoint(state, 3 * scale),
                             offset + randomPoint(state, 3 * scale),
                             offset + randomPoint(state, 3 * scale)};
        if (trial % 2 == 1) {  // onto the receiver's plane, then under it
            const float below = scale * std::pow(10.0f, -6.0f + float(trial % 9) * 0.5f);
            for (shared::vec3& corner : c) {
                const float h = shared::dot(receiver.normal, corner - receiver.a);
                corner = corner - receiver.normal * (h + below);
            }
        }
        const shared::PatchGeometry light = shared::makePatchGeometry(c[0], c[1], c[2]);
        if (!(receiver.area > 0) || !(light.area > 0)) continue;
        if (!lightHiddenFrom(receiver, light)) {
            ++seen;
            continue;
        }
        ++hidden;
        for (const shared::vec3& x : pointsOn(receiver, state)) {
            ASSERT_EQ(shared::pointToTriangleFactor(x, receiver.normal, light), 0.0f)
                << "trial " << trial;
        }
    }
    // Both answers occur, so the test exercises the predicate.
    EXPECT_GT(hidden, 500);
    EXPECT_GT(seen, 500);
}

TEST(EmitterLights, LightsFacingAPatchOrGrazingItAreNotHidden) {
    // A unit receiver in z = 0 facing +z.
    shared::PatchGeometry receiver = shared::makePatchGeometry({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    ASSERT_GT(receiver.normal.z, 0.99f);
    // Above it, facing down: seen. Facing up: the receiver is behind it, hidden.
    const auto light = [](float z, bool down) {
        return down ? shared::makePatchGeometry({0, 0, z}, {0, 1, z}, {1, 0, z})
                    : shared::makePatchGeometry({0, 0, z}, {1, 0, z}, {0, 1, z});
    };
    EXPECT_FALSE(lightHiddenFrom(receiver, light(1.0f, true)));
    EXPECT_TRUE(lightHiddenFrom(receiver, light(1.0f, false)));
    // Below the receiver's plane, facing up at it from under: hidden (behind the receiver).
    EXPECT_TRUE(lightHiddenFrom(receiver, light(-1.0f, false)));
    // In the receiver's own plane (an emitting neighbour), or a rounding below it: not hidden,
    // as the factor's tolerances may keep part of it.
    const shared::PatchGeometry beside =
        shared::makePatchGeometry({2, 0, 0}, {3, 0, -1e-7f}, {2, 1, 0});
    EXPECT_FALSE(lightHiddenFrom(receiver, beside));
    // A patch lies in its own plane: never hidden from itself.
    EXPECT_FALSE(lightHiddenFrom(receiver, receiver));
}

}  // namespace
}  // namespace daisy
