// Edge-adaptive supersampling (image/edge_sampling.h): which pixels take the edge sample count,
// and that an edge pixel's coverage is then its analytic area fraction at the finer grid.
#include "image/edge_sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "image/camera.h"
#include "image/origin_camera.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using test::originCamera;

// x at depth `depth` (z = -depth) of image column position xImage in a square image of `width`.
double xAt(double xImage, int width, double depth) {
    return (2 * xImage / width - 1) * std::tan(0.5 * 1.0471975511965976) * depth;
}

RenderSettings square(int size, int spp) {
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.samplesPerPixel = spp;
    return settings;
}

// A vertical silhouette at image position xEdge: the quad covers x < xEdge, nothing behind it.
PatchMesh silhouette(double xEdge, int width) {
    const double edge = xAt(xEdge, width, 1);
    TriangleMesh triangles;
    verify::addQuad(triangles, {-10, -10, -1}, {edge, -10, -1}, {edge, 10, -1}, {-10, 10, -1});
    return verify::patchesOf(triangles);
}

TEST(EdgeSampling, TheColumnsEitherSideOfASilhouetteAndNoOthers) {
    const int size = 8;
    const PatchMesh mesh = silhouette(3.3, size);  // centres 2.5 hit, 3.5 miss
    const auto sides = edgeAdaptiveSides(mesh, originCamera(), square(size, 1), 16);
    ASSERT_TRUE(sides.ok()) << sides.error().message;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            EXPECT_EQ(int((*sides)[std::size_t(y * size + x)]), x == 2 || x == 3 ? 4 : 1)
                << x << " " << y;
        }
    }
    // The base count stays where it is larger than the edge count.
    const auto uniform = edgeAdaptiveSides(mesh, originCamera(), square(size, 9), 4);
    ASSERT_TRUE(uniform.ok());
    for (const uint8_t side : *uniform)
        EXPECT_EQ(int(side), 3);
}

TEST(EdgeSampling, PatchesOfOnePlaneAreOneSurface) {
    // A subdivided quad filling the view: many patches, one plane, one material.
    TriangleMesh triangles;
    verify::addGrid(triangles, {-4, -4, -1}, {8, 0, 0}, {0, 8, 0}, 16, 16);
    const PatchMesh mesh = verify::patchesOf(triangles);
    const auto sides = edgeAdaptiveSides(mesh, originCamera(), square(16, 1), 16);
    ASSERT_TRUE(sides.ok());
    for (const uint8_t side : *sides)
        EXPECT_EQ(int(side), 1);
}

TEST(EdgeSampling, AFaceInFrontOfAParallelWallAndACreaseAreEdges) {
    const int size = 16;
    // A wall at depth 2 and, in front of it at depth 1, a face over image columns [4.3, 11.7)
    // and rows [4.3, 11.7); same material, parallel planes.
    TriangleMesh triangles;
    verify::addQuad(triangles, {-8, -8, -2}, {8, -8, -2}, {8, 8, -2}, {-8, 8, -2});
    const double lo = xAt(4.3, size, 1), hi = xAt(11.7, size, 1);
    verify::addQuad(triangles, {lo, lo, -1}, {hi, lo, -1}, {hi, hi, -1}, {lo, hi, -1});
    const auto sides =
        edgeAdaptiveSides(verify::patchesOf(triangles), originCamera(), square(size, 1), 4);
    ASSERT_TRUE(sides.ok());
    // Image rows run top to bottom, the face is symmetric: columns and rows 3, 4, 11 and 12
    // border it (within [3, 12]).
    const auto border = [](int i) { return i == 3 || i == 4 || i == 11 || i == 12; };
    const auto inside = [](int i) { return i >= 3 && i <= 12; };
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const bool edge = (border(x) && inside(y)) || (border(y) && inside(x));
            EXPECT_EQ(int((*sides)[std::size_t(y * size + x)]), edge ? 2 : 1) << x << " " << y;
        }
    }

    // A crease: the floor y = -1 meeting the wall z = -3, seen from the origin; the pixels the
    // crease line crosses are edges, those well inside either face are not.
    TriangleMesh room;
    verify::addQuad(room, {-9, -1, 0}, {9, -1, 0}, {9, -1, -3}, {-9, -1, -3});  // floor, +y
    verify::addQuad(room, {-9, -1, -3}, {9, -1, -3}, {9, 9, -3}, {-9, 9, -3});  // wall, +z
    const auto creased =
        edgeAdaptiveSides(verify::patchesOf(room), originCamera(), square(size, 1), 4);
    ASSERT_TRUE(creased.ok());
    // The crease is at y = -1, z = -3: image row position (1 + (1 / 3) / tan 30 deg) * 8.
    const double row = (1 + (1.0 / 3) / std::tan(0.5 * 1.0471975511965976)) * size / 2;
    const int crease = int(std::floor(row));
    for (int x = 0; x < size; ++x) {
        EXPECT_EQ(int((*creased)[std::size_t(crease * size + x)]), 2) << x;
        EXPECT_EQ(int((*creased)[std::size_t((crease - 3) * size + x)]), 1) << x;
        EXPECT_EQ(int((*creased)[std::size_t((crease + 3) * size + x)]), 1) << x;
    }
}

// With the map, the pixel the edge crosses covers the edge grid's rounding of its area fraction
// to 1 / N^2 (renderer_test.cpp's EdgeCoverageIsTheAreaFraction for a uniform grid), every
// other pixel is exactly in or out.
TEST(EdgeSampling, EdgePixelCoverageIsTheAreaFractionAtTheEdgeGrid) {
    const int size = 8;
    for (const int edgeSpp : {4, 16, 64}) {
        const int side = int(std::lround(std::sqrt(double(edgeSpp))));
        for (const double xEdge : {3.3, 4.8, 2.1, 5.55}) {
            const PatchMesh mesh = silhouette(xEdge, size);
            RenderSettings settings = square(size, 1);
            const auto sides = edgeAdaptiveSides(mesh, originCamera(), settings, edgeSpp);
            ASSERT_TRUE(sides.ok());
            settings.pixelSides = *sides;
            const std::vector<float> corners(mesh.patchCount() * 3, 1.0f);
            const float background = 0;
            const auto image =
                renderCornerValues(mesh, originCamera(), settings, corners, 1, {&background, 1});
            ASSERT_TRUE(image.ok()) << image.error().message;
            const int pixel = int(std::floor(xEdge));
            const double fraction = xEdge - pixel;
            const int columns = side * side;  // multi-jittered: N^2 sample columns
            const double rounded = std::ceil(fraction * columns - 0.5) / columns;
            for (int y = 0; y < size; ++y) {
                for (int x = 0; x < size; ++x) {
                    const double expected = x < pixel ? 1.0 : x > pixel ? 0.0 : rounded;
                    EXPECT_NEAR(image->at(x, y)[0], expected, 1e-6)
                        << "edge spp " << edgeSpp << " edge " << xEdge << " pixel " << x;
                }
            }
        }
    }
}

TEST(EdgeSampling, RefusesOversizedGridsAndAMismatchedMap) {
    const PatchMesh mesh = silhouette(3.3, 8);
    EXPECT_FALSE(edgeAdaptiveSides(mesh, originCamera(), square(8, 1), 256 * 256).ok());
    RenderSettings settings = square(8, 1);
    const std::vector<uint8_t> tooShort(10, 1);
    settings.pixelSides = tooShort;
    const std::vector<float> corners(mesh.patchCount() * 3, 1.0f);
    const float background = 0;
    EXPECT_FALSE(
        renderCornerValues(mesh, originCamera(), settings, corners, 1, {&background, 1}).ok());
}

}  // namespace
}  // namespace daisy
