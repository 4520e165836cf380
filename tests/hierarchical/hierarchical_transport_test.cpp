// The hierarchical transport (hierarchical/hierarchical_transport.h) against oracles: closed-form
// factors (Howell C-11), the matrix path on a scene small enough for both, the white and the
// fluorescent furnace, reciprocity per link, capped row sums and the solvers.
#include "hierarchical/hierarchical_transport.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>

#include "pipeline/session.h"
#include "radiosity/patch_exposure.h"
#include "radiosity/solver_test_util.h"
#include "test_util.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using solvertest::diagonalOperator;
using solvertest::makeSystem;
using solvertest::matrixOperator;

// A grey system over `mesh` (m = 1): reflectance rho, emission e on every patch.
RadiositySystem greySystem(const PatchMesh& mesh, double rho, double e) {
    RadiositySystem system = makeSystem(uint32_t(mesh.patchCount()), 1, {diagonalOperator({rho})});
    system.wavelengthsNm = {555};
    system.areas = mesh.areas;
    std::fill(system.emission.begin(), system.emission.end(), e);
    return system;
}

FormFactorSettings quietSettings() {
    FormFactorSettings settings;
    settings.progress = false;
    return settings;
}

std::shared_ptr<const HierarchicalTransport> build(const PatchMesh& mesh,
                                                   const RadiositySystem& system,
                                                   HierarchySettings hierarchy = {}) {
    auto exposure = patchExposure(mesh);
    EXPECT_TRUE(exposure.ok());
    if (!exposure.ok()) return nullptr;
    auto built = buildHierarchicalTransport(mesh, *exposure, system, hierarchy, quietSettings());
    EXPECT_TRUE(built.ok()) << (built.ok() ? "" : built.error().message);
    return built.ok() ? *built : nullptr;
}

// The area-weighted factor from patches [a0, a1) to [b0, b1) through a gather of B = 1 on the
// second range: sum_i A_i G_i / A_A.
double groupFactor(const PatchMesh& mesh, const Transport& transport, uint32_t a0, uint32_t a1,
                   uint32_t b0, uint32_t b1) {
    std::vector<double> b(mesh.patchCount(), 0.0), g(mesh.patchCount());
    std::fill(b.begin() + b0, b.begin() + b1, 1.0);
    transport.gather(b, 1, g);
    double flux = 0, area = 0;
    for (uint32_t i = a0; i < a1; ++i)
        flux += mesh.areas[i] * g[i], area += mesh.areas[i];
    return flux / area;
}

// Two unit squares 1 apart, 16 x 16 quads each (1,024 patches): the far field gives Howell C-11
// to its accuracy (the point-to-point coupling misses the second-order term of the nodes'
// extent, which the oracle's first-order bound keeps under 0.5% here), and the links are far
// fewer than the pairs.
TEST(HierarchicalTransport, ParallelSquaresFactorIsHowellC11) {
    const PatchMesh mesh = verify::patchesOf(verify::parallelSquares(16, 1));
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    const auto transport = build(mesh, system);
    ASSERT_TRUE(transport);
    EXPECT_EQ(transport->checkStructure(), "");
    const uint32_t half = uint32_t(mesh.patchCount() / 2);
    EXPECT_NEAR(groupFactor(mesh, *transport, 0, half, half, 2 * half), verify::kHowellC11,
                5e-3 * verify::kHowellC11);
    EXPECT_NEAR(groupFactor(mesh, *transport, half, 2 * half, 0, half), verify::kHowellC11,
                5e-3 * verify::kHowellC11);
    const LinkStats& stats = transport->linkStats();
    EXPECT_GT(stats.farLinks, 0u);
    EXPECT_LT(stats.nearEntries + 2 * stats.farLinks, uint64_t(half) * half);
}

// Pairs within the visibility share are kept by Russian roulette and carry their estimate over
// the probability (hierarchical_links.h). With the share at 3 epsilon, more than half of the
// far pairs between two parallel unit squares 1 apart (16 x 16 quads each, nothing between)
// are left out by it, and the factor must still be Howell C-11 to the roulette's noise
// (measured 0.993 of it with 689 links and 740 pairs left out; the kept links not scaled by
// their probability gave 0.51).
TEST(HierarchicalTransport, RouletteKeepsTheExpectedTransport) {
    const PatchMesh mesh = verify::patchesOf(verify::parallelSquares(16, 1));
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    HierarchySettings hierarchy;
    hierarchy.linkTolerance = 1e-4;
    hierarchy.visibilityShare = 3;
    const auto transport = build(mesh, system, hierarchy);
    ASSERT_TRUE(transport);
    const LinkStats& stats = transport->linkStats();
    EXPECT_GT(stats.rouletteDropped, stats.farLinks / 2);
    const uint32_t half = uint32_t(mesh.patchCount() / 2);
    EXPECT_NEAR(groupFactor(mesh, *transport, 0, half, half, 2 * half), verify::kHowellC11,
                0.02 * verify::kHowellC11);
    EXPECT_NEAR(groupFactor(mesh, *transport, half, 2 * half, 0, half), verify::kHowellC11,
                0.02 * verify::kHowellC11);
}

// Two unit squares 2 apart, 8 x 8 quads each, with a plate halfway covering x < 0.5: the
// reflection x -> 1 - x swaps blocked and open segments, so the factor between them is exactly
// half of Howell C-11 at distance 2 (verify/scenes.h). The far links' visibility gives it to
// 0.5% at the default tolerance (measured 0.5004 of C-11) and to 5% with the links high in the
// tree (1e-3: 60 far links and 51 pairs left out by the roulette, 0.508), where a partly
// visible pair is linked on one batch of segments and its V estimated on another.
TEST(HierarchicalTransport, HalfOccludedSquaresShareExactlyHalf) {
    const PatchMesh mesh = verify::patchesOf(verify::halfOccludedSquares());
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    for (const auto& [tolerance, within] : {std::pair{1e-6, 0.005}, std::pair{1e-3, 0.05}}) {
        HierarchySettings hierarchy;
        hierarchy.linkTolerance = tolerance;
        const auto transport = build(mesh, system, hierarchy);
        ASSERT_TRUE(transport);
        EXPECT_GT(transport->linkStats().farLinks, 50u);
        EXPECT_GT(transport->linkStats().hidden, 0u);
        EXPECT_NEAR(groupFactor(mesh, *transport, 0, 128, 128, 256),
                    0.5 * verify::kHowellC11Distance2, within * 0.5 * verify::kHowellC11Distance2)
            << "tolerance " << tolerance;
    }
}

// A wall (x = 0, facing -x, 8 x 8 quads) standing on a floor that runs past its plane (x from
// -1 to 1.5, 20 x 8 quads): the wall sees the unit square of floor in front of it, Howell C-14,
// and nothing behind. At a coarse tolerance the wall's nodes and the floor's pair up while
// their whole exchange is within epsilon, some with the floor's centroid behind the wall: such
// planar pairs are linked with the mean of their segments' own kernel (unbiased; dropped
// before, the factor read 1.1% low). Over 16 seeds the mean is C-14 to 0.6% (measured 0.4%).
TEST(HierarchicalTransport, AFloorRunningPastAWallsPlaneGivesItHowellC14) {
    TriangleMesh triangles;
    verify::addGrid(triangles, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 8, 8);
    verify::addGrid(triangles, {-1, 0, 0}, {2.5, 0, 0}, {0, 1, 0}, 20, 8);
    const PatchMesh mesh = verify::patchesOf(triangles);
    ASSERT_EQ(mesh.patchCount(), 448u);
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    auto exposure = patchExposure(mesh);
    ASSERT_TRUE(exposure.ok());
    HierarchySettings hierarchy;
    hierarchy.linkTolerance = 1e-2;
    double mean = 0;
    for (uint64_t seed = 1; seed <= 16; ++seed) {
        FormFactorSettings settings = quietSettings();
        settings.seed = seed;
        auto transport = buildHierarchicalTransport(mesh, *exposure, system, hierarchy, settings);
        ASSERT_TRUE(transport.ok()) << transport.error().message;
        EXPECT_EQ((*transport)->checkStructure(), "");
        mean += groupFactor(mesh, **transport, 0, 128, 128, 448) / 16;
    }
    EXPECT_NEAR(mean, verify::kHowellC14, 6e-3 * verify::kHowellC14);
}

// A 0.5 m square 4 m above a unit square, emitting, as 2 triangles or as a 32 x 32 grid of
// 2,048: the cluster of small coplanar squares transports what the one square does, to the
// oracle's bound (within 0.5%), and both are the point-to-point factor A_s / (pi d^2) less the
// second-order term of the squares' extent (2 E[s^2] / d^2 = 2.6%, s the offsets, parallel
// plates: 1 / 6 + 1 / 24 over 16), to 0.5%.
TEST(HierarchicalTransport, AClusterOfSmallSquaresTransportsWhatOneSquareDoes) {
    auto scene = [](int n) {
        TriangleMesh mesh;
        verify::addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1);  // receiver, faces +z
        verify::addGrid(mesh, {0.25, 0.75, 4}, {0.5, 0, 0}, {0, -0.5, 0}, n, n);  // faces -z
        return verify::patchesOf(mesh);
    };
    double received[2];
    for (int k = 0; k < 2; ++k) {
        const PatchMesh mesh = scene(k == 0 ? 1 : 32);
        RadiositySystem system = greySystem(mesh, 0.5, 1);
        std::fill_n(system.emission.begin(), 2, 0.0);  // only the small square emits
        const auto transport = build(mesh, system);
        ASSERT_TRUE(transport);
        received[k] = groupFactor(mesh, *transport, 0, 2, 2, uint32_t(mesh.patchCount()));
    }
    const double pointToPoint = 0.25 / (M_PI * 16);
    const double expected = pointToPoint * (1 - 2 * (1.0 / 6 + 1.0 / 24) / 16);
    EXPECT_NEAR(received[1], received[0], 5e-3 * received[0]);
    EXPECT_NEAR(received[0], expected, 5e-3 * expected);
}

// A lit room around a floating closed box whose material is double-sided (as Blender exports
// every material): the box's back faces enclose a cavity no light reaches (a dark region of the
// survey). Its patches neither send nor receive, so no pair with one of them is linked, while
// the box's outside is lit.
TEST(HierarchicalTransport, ADarkCavityGetsNoLinks) {
    TriangleMesh triangles = verify::unitCubeRoom(4);
    const uint32_t roomTriangles = uint32_t(triangles.triangleCount());
    verify::addSolidBox(triangles, {0.35, 0.35, 0.35}, {0.3, 0.3, 0.3}, 4);
    for (uint32_t t = roomTriangles; t < triangles.triangleCount(); ++t)
        triangles.materials[t] = 1;
    const uint8_t doubleSided[2] = {0, 1};
    auto mesh = buildPatchMesh(triangles, 0, UINT32_MAX, doubleSided);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    const uint32_t n = uint32_t(mesh->patchCount()), box = n - roomTriangles;  // fronts + backs
    ASSERT_EQ(box % 2, 0u);
    const uint32_t backs = n - box / 2;  // back patches follow every front patch
    RadiositySystem system = greySystem(*mesh, 0.5, 0);
    std::fill_n(system.emission.begin(), roomTriangles, 1.0);  // the room's walls emit
    const auto transport = build(*mesh, system);
    ASSERT_TRUE(transport);
    EXPECT_EQ(groupFactor(*mesh, *transport, backs, n, backs, n), 0.0);
    EXPECT_GT(groupFactor(*mesh, *transport, roomTriangles, backs, 0, roomTriangles), 0.1);
    // No pair with a cavity patch is even tried: against the room with the box single-sided
    // (no cavity faces at all), the same near factors, no hidden pair, and few more node pairs
    // examined (the tree splits differently). With the cavity's yield counted, 83% more pairs
    // were examined, 50 of them hidden and shot at with 400 rays, and 2 factors more stored.
    const uint8_t singleSided[2] = {0, 0};
    auto plain = buildPatchMesh(triangles, 0, UINT32_MAX, singleSided);
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    RadiositySystem plainSystem = greySystem(*plain, 0.5, 0);
    std::fill_n(plainSystem.emission.begin(), roomTriangles, 1.0);
    const auto without = build(*plain, plainSystem);
    ASSERT_TRUE(without);
    const LinkStats& with = transport->linkStats();
    const LinkStats& other = without->linkStats();
    EXPECT_EQ(with.nearEntries, other.nearEntries);
    EXPECT_EQ(with.hidden, 0u);
    EXPECT_LT(double(with.candidates), 1.2 * double(other.candidates));
}

// Two 0.2 m squares 2 mm apart facing each other in a room of large patches whose walls emit:
// of the few survey rays (hierarchical_transport.cpp) that leave the gap, reciprocity lets
// back in about the patches' area ratio (1 in 400), so none lands on the squares' inner faces,
// but theirs land on the walls: they are in the walls' lit region, and exchange what Howell
// C-11 gives, within 2% (the near factors' accuracy). Light was counted only on patches a path
// of survey rays led to from an emitter, and the pair carried nothing: their factor was 0,
// their rows filled up with the walls' light.
TEST(HierarchicalTransport, PatchesNoSurveyRayReachesInALitRegionExchangeLight) {
    TriangleMesh triangles = verify::unitCubeRoom(1);
    const uint32_t room = uint32_t(triangles.triangleCount());
    verify::addGrid(triangles, {0.4, 0.4, 0.499}, {0.2, 0, 0}, {0, 0.2, 0}, 4, 4);  // faces +z
    verify::addGrid(triangles, {0.4, 0.4, 0.501}, {0, 0.2, 0}, {0.2, 0, 0}, 4, 4);  // faces -z
    const PatchMesh mesh = verify::patchesOf(triangles);
    const uint32_t n = uint32_t(mesh.patchCount()), half = (n - room) / 2;
    RadiositySystem system = greySystem(mesh, 0.5, 0);
    std::fill_n(system.emission.begin(), room, 1.0);
    const auto transport = build(mesh, system);
    ASSERT_TRUE(transport);
    const double expected = verify::parallelRectangles(0.2, 0.2, 0.002);
    EXPECT_NEAR(groupFactor(mesh, *transport, room, room + half, room + half, n), expected,
                0.02 * expected);
    EXPECT_NEAR(groupFactor(mesh, *transport, room + half, n, room, room + half), expected,
                0.02 * expected);
}

// A floor of 6 x 6 tiles (0.16 m with 1 cm gaps) under a lamp 1 m above (8 x 8 quads facing
// down), and a sheet 5 mm under the tiles, as a tiled floor's grout often is: the sheet's
// patches are sheltered (their survey rays end on the tiles' undersides) and their own subtree,
// so the tiles' factor to the lamp is what it is without the sheet, within 1% (the tree splits
// differently), with links at the top of the tree (a coarse tolerance). In one node with the
// tiles the sheet shared their links' visibility, sampled over both, and the tiles' factor came
// out 23% low (0.153 against 0.1998); sheltered only within a tenth of a patch's size, some of
// the sheet's patches were not, and it was 3.9% low.
TEST(HierarchicalTransport, ASheetUnderFloorTilesDoesNotShadeThem) {
    const auto scene = [](bool sheet) {
        TriangleMesh triangles;
        for (int x = 0; x < 8; ++x) {
            for (int y = 0; y < 8; ++y) {
                const double x0 = x / 8.0, x1 = (x + 1) / 8.0, y0 = y / 8.0, y1 = (y + 1) / 8.0;
                verify::addQuad(triangles, {x0, y0, 1}, {x0, y1, 1}, {x1, y1, 1}, {x1, y0, 1});
            }
        }
        for (int x = 0; x < 6; ++x) {
            for (int y = 0; y < 6; ++y) {
                const double x0 = 0.005 + x / 6.0, x1 = x0 + 1 / 6.0 - 0.01;
                const double y0 = 0.005 + y / 6.0, y1 = y0 + 1 / 6.0 - 0.01;
                verify::addQuad(triangles, {x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0});
            }
        }
        for (int x = 0; sheet && x < 8; ++x) {
            for (int y = 0; y < 8; ++y) {
                const double x0 = x / 8.0, x1 = (x + 1) / 8.0, y0 = y / 8.0, y1 = (y + 1) / 8.0;
                verify::addQuad(triangles, {x0, y0, -0.005}, {x1, y0, -0.005}, {x1, y1, -0.005},
                                {x0, y1, -0.005});
            }
        }
        return verify::patchesOf(triangles);
    };
    const uint32_t lamp = 128, tiles = lamp + 72;
    double factors[2];
    for (const bool sheet : {false, true}) {
        const PatchMesh mesh = scene(sheet);
        RadiositySystem system = greySystem(mesh, 0.5, 0);
        std::fill_n(system.emission.begin(), lamp, 1.0);
        HierarchySettings coarse;  // links at the top of the tree, where the nodes would mix
        coarse.linkTolerance = 0.02;
        const auto transport = build(mesh, system, coarse);
        ASSERT_TRUE(transport);
        factors[sheet] = groupFactor(mesh, *transport, lamp, tiles, 0, lamp);
    }
    EXPECT_GT(factors[0], 0.15);  // unit squares 1 apart: 0.1998 (Howell C-11)
    // 2%: at this tolerance the lamp and the tiles meet past the far field's aperture, where a
    // link's weight is its few segments' mean kernel (unbiased, not exact); the shading this
    // guards against was 15-20%.
    EXPECT_NEAR(factors[1], factors[0], 0.02 * factors[0]) << factors[0];
}

// The black-light box's back wall behind its eight posters (2 cm deep boxes on the wall): the
// wall patches that run partly under a poster (0 < phi < 1, radiosity/patch_exposure.h) get
// what the matrix path's F gives them, summed over their row: each within 15% (measured
// 0.87-1.06 of the matrix path's, 162 patches), together within 2% (0.988). Sampled over the
// whole patches, the segments starting under a poster made every pair of such a patch look
// partly visible, refined down to single patches, each level another chance for all its
// segments to start under the poster and the pair to be dropped as hidden: their rows came out
// 0.44-1.33 of the matrix path's, together 0.972.
TEST(HierarchicalTransport, WallPatchesPartlyUnderPostersGetTheMatrixPathsRows) {
    std::vector<double> rows[2];
    std::vector<float> phi;
    std::vector<double> areas;
    for (const TransportKind kind : {TransportKind::Matrix, TransportKind::Hierarchical}) {
        SessionSettings settings;
        settings.scenePath = test::assetPath("scenes/blacklight_box.gltf");
        settings.backend = "cpu";
        settings.formFactors.progress = false;
        settings.logStages = false;
        settings.transport = kind;
        auto session = Session::open(settings);
        ASSERT_TRUE(session.ok()) << session.error().message;
        ASSERT_TRUE(session->buildFormFactors().ok());
        const auto sums = session->transport().rowSums();
        rows[kind == TransportKind::Hierarchical].assign(sums.begin(), sums.end());
        auto exposure = session->exposure();
        ASSERT_TRUE(exposure.ok());
        phi = (*exposure)->fraction;
        areas = session->patches().areas;
    }
    // The back wall is the scene's third mesh: its patches 2,704 to 3,483 (z = 0).
    double sum[2] = {0, 0};
    int cut = 0;
    for (uint32_t i = 2704; i < 3484; ++i) {
        if (!(phi[i] > 0 && phi[i] < 1)) continue;
        ++cut;
        EXPECT_NEAR(rows[1][i], rows[0][i], 0.15 * rows[0][i]) << "patch " << i;
        for (int k = 0; k < 2; ++k)
            sum[k] += areas[i] * rows[k][i];
    }
    EXPECT_GT(cut, 100);
    EXPECT_NEAR(sum[1], sum[0], 0.02 * sum[0]);
}

// A closed room (no ray escapes): every row is scaled to exactly 1, so the white furnace
// B = E / (1 - rho) holds to the solver's tolerance, and so does the fluorescent furnace
// B = (I - M)^-1 E (solver_test.cpp's oracle).
TEST(HierarchicalTransport, WhiteAndFluorescentFurnacesHold) {
    const PatchMesh mesh = verify::patchesOf(verify::unitCubeRoom(8));
    const RadiositySystem white = greySystem(mesh, 0.5, 1);
    const auto transport = build(mesh, white);
    ASSERT_TRUE(transport);
    for (double sum : transport->rowSums())
        ASSERT_EQ(sum, 1.0);
    SolverSettings settings;
    settings.tolerance = 1e-9;
    auto solved = transport->solve(white, settings);
    ASSERT_TRUE(solved.ok()) << solved.error().message;
    for (double b : solved->radiosity)
        ASSERT_NEAR(b, 2.0, 1e-4);

    RadiositySystem fluorescent =
        makeSystem(uint32_t(mesh.patchCount()), 3,
                   {matrixOperator(3, {0.5, 0, 0, 0.3, 0.4, 0, 0.1, 0.2, 0.6})});
    fluorescent.areas = mesh.areas;
    for (std::size_t i = 0; i < mesh.patchCount(); ++i)
        std::copy_n(std::vector<double>{2, 1, 0.5}.data(), 3, fluorescent.emission.data() + 3 * i);
    const double b0 = 4, b1 = (1 + 0.3 * b0) / 0.6, b2 = (0.5 + 0.1 * b0 + 0.2 * b1) / 0.4;
    auto glowing = transport->solve(fluorescent, settings);
    ASSERT_TRUE(glowing.ok()) << glowing.error().message;
    for (std::size_t i = 0; i < mesh.patchCount(); ++i) {
        ASSERT_NEAR(glowing->radiosity[3 * i + 0], b0, 1e-4 * b0);
        ASSERT_NEAR(glowing->radiosity[3 * i + 1], b1, 1e-4 * b1);
        ASSERT_NEAR(glowing->radiosity[3 * i + 2], b2, 1e-4 * b2);
    }
}

// The same room with a double-sided material, as Blender exports it: the walls' outer faces
// send every ray to the void, but they are a region of their own, so the inside is still closed
// and its rows sum to exactly 1 (the white furnace holds there), while the outer faces receive
// nothing. When the outer faces' escaping rays counted against the whole scene, no row was
// filled and the double-sided Blender-style Cornell box came out 1.2% dark.
TEST(HierarchicalTransport, TheInsideOfADoubleSidedRoomIsClosed) {
    const uint8_t doubleSided[1] = {1};
    auto mesh = buildPatchMesh(verify::unitCubeRoom(8), 0, UINT32_MAX, doubleSided);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    const uint32_t n = uint32_t(mesh->patchCount()), inside = n / 2;  // then the back faces
    const RadiositySystem white = greySystem(*mesh, 0.5, 1);
    const auto transport = build(*mesh, white);
    ASSERT_TRUE(transport);
    for (uint32_t i = 0; i < n; ++i)
        ASSERT_EQ(transport->rowSums()[i], i < inside ? 1.0 : 0.0) << "patch " << i;
    SolverSettings settings;
    settings.tolerance = 1e-9;
    auto solved = transport->solve(white, settings);
    ASSERT_TRUE(solved.ok()) << solved.error().message;
    for (uint32_t i = 0; i < n; ++i)
        ASSERT_NEAR(solved->radiosity[i], i < inside ? 2.0 : 1.0, 1e-4) << "patch " << i;
}

// A room with a hole in one wall (one of its 8 x 8 cells): its one region is open (rays escape
// through the hole), but the patches of the holed wall cannot see the hole, their own plane:
// every ray of theirs lands, and their rows are filled to exactly 1, as in a closed room,
// where their links alone sum to 0.95-1 of it (left to the caps, a row over 1 is cut and one
// under it kept: the far field's noise turns into a loss). Patches that see the hole keep
// rows under 1.
TEST(HierarchicalTransport, RowsThatSeeNoOpeningAreFilledInAnOpenRoom) {
    TriangleMesh triangles = verify::unitCubeRoom(8);
    // The wall y = 0 is the third face, triangles 256 to 383, two a cell: drop cell (3, 3).
    const std::size_t hole = 256 + 2 * (3 * 8 + 3);
    triangles.triangles.erase(triangles.triangles.begin() + std::ptrdiff_t(hole),
                              triangles.triangles.begin() + std::ptrdiff_t(hole + 2));
    triangles.materials.erase(triangles.materials.begin() + std::ptrdiff_t(hole),
                              triangles.materials.begin() + std::ptrdiff_t(hole + 2));
    const PatchMesh mesh = verify::patchesOf(triangles);
    const auto transport = build(mesh, greySystem(mesh, 0.5, 1));
    ASSERT_TRUE(transport);
    int filled = 0, under = 0;
    for (uint32_t i = 0; i < mesh.patchCount(); ++i) {
        const double row = transport->rowSums()[i];
        if (i >= 256 && i < 382) {
            EXPECT_EQ(row, 1.0) << "patch " << i << " of the holed wall";
            filled += row == 1.0;
        }
        under += row < 0.999;
    }
    EXPECT_EQ(filled, 126);
    EXPECT_GT(under, 0);
}

// Jacobi and Gauss-Seidel land on the same B; Southwell, which needs F's columns, says why not.
TEST(HierarchicalTransport, SolversAgreeAndSouthwellIsRefused) {
    const PatchMesh mesh = verify::patchesOf(verify::parallelSquares(8, 1));
    RadiositySystem system = greySystem(mesh, 0.7, 0);
    std::fill_n(system.emission.begin(), 64, 1.0);  // half of one square emits
    const auto transport = build(mesh, system);
    ASSERT_TRUE(transport);
    SolverSettings settings;
    settings.tolerance = 1e-10;
    settings.kind = SolverKind::Jacobi;
    auto jacobi = transport->solve(system, settings);
    settings.kind = SolverKind::GaussSeidel;
    auto gaussSeidel = transport->solve(system, settings);
    ASSERT_TRUE(jacobi.ok() && gaussSeidel.ok());
    EXPECT_TRUE(jacobi->converged && gaussSeidel->converged);
    for (std::size_t i = 0; i < jacobi->radiosity.size(); ++i)
        EXPECT_NEAR(jacobi->radiosity[i], gaussSeidel->radiosity[i], 1e-8);
    settings.kind = SolverKind::Southwell;
    auto southwell = transport->solve(system, settings);
    ASSERT_FALSE(southwell.ok());
    EXPECT_NE(southwell.error().message.find("southwell"), std::string::npos);
}

SessionSettings cornellSettings(double maxEdge) {
    SessionSettings settings;
    settings.scenePath = test::assetPath("scenes/cornell_box.gltf");
    settings.backend = "cpu";
    settings.subdivideMaxEdge = maxEdge;
    settings.formFactors.progress = false;
    settings.logStages = false;
    return settings;
}

// The disk cache of the links (pipeline/links_cache.h): a second session reads the transport
// the first one built and stored, and solves to the same B bit for bit; a damaged entry is
// refused with a warning naming it, and the links are built again.
TEST(HierarchicalTransport, TheLinksCacheRestoresTheTransportExactly) {
    const auto dir = test::testTempDir() / "cache";
    SessionSettings settings = cornellSettings(0.1);
    settings.transport = TransportKind::Hierarchical;
    settings.cacheDirectory = dir;
    std::vector<double> radiosity[2];
    for (int k = 0; k < 2; ++k) {
        auto session = Session::open(settings);
        ASSERT_TRUE(session.ok()) << session.error().message;
        auto report = session->buildFormFactors();
        ASSERT_TRUE(report.ok()) << report.error().message;
        EXPECT_EQ(report->fromCache, k == 1);
        EXPECT_EQ(session->finishCacheWrite(), "");
        EXPECT_TRUE(session->formFactorsCached());
        EXPECT_EQ(session->transport().checkStructure(), "");
        auto solved = session->transport().solve(session->system(), SolverSettings{});
        ASSERT_TRUE(solved.ok()) << solved.error().message;
        radiosity[k] = solved->radiosity;
    }
    EXPECT_EQ(radiosity[0], radiosity[1]);

    std::filesystem::path entry;
    for (const auto& file : std::filesystem::directory_iterator(dir)) {
        if (file.path().extension() == ".dhl") entry = file.path();
    }
    ASSERT_FALSE(entry.empty());
    {
        std::fstream file(entry, std::ios::in | std::ios::out | std::ios::binary);
        file.seekp(200);
        file.put('\x5a');
    }
    auto session = Session::open(settings);
    ASSERT_TRUE(session.ok());
    auto report = session->buildFormFactors();
    ASSERT_TRUE(report.ok()) << report.error().message;
    EXPECT_FALSE(report->fromCache);
    EXPECT_NE(report->cacheWarning.find(entry.filename().string()), std::string::npos)
        << report->cacheWarning;
    EXPECT_NE(report->cacheWarning.find("building the links"), std::string::npos)
        << report->cacheWarning;
    auto solved = session->transport().solve(session->system(), SolverSettings{});
    ASSERT_TRUE(solved.ok());
    EXPECT_EQ(solved->radiosity, radiosity[0]);
}

// gatherFrom, which the image's final gather takes the emitters' direct light out with, skips
// the far links from nodes with no source below them: it gives what a whole gather of the
// masked radiosity gives, to rounding (the planar links summed in another order), for the
// receivers asked for and nothing for the others.
TEST(HierarchicalTransport, GatherFromSomeSourcesIsTheGatherOfTheirLight) {
    // A room with a cylinder of 24 facets standing in it: its nodes that are not planar have
    // far links (the vector form).
    TriangleMesh triangles = verify::unitCubeRoom(6);
    for (int k = 0; k < 24; ++k) {
        const double a0 = 2 * M_PI * k / 24, a1 = 2 * M_PI * (k + 1) / 24;
        const Vec3d p0{0.5 + 0.1 * std::cos(a0), 0, 0.5 + 0.1 * std::sin(a0)};
        const Vec3d p1{0.5 + 0.1 * std::cos(a1), 0, 0.5 + 0.1 * std::sin(a1)};
        verify::addGrid(triangles, p0, {0, 0.6, 0}, p1 - p0, 3, 1);  // faces outwards
    }
    const PatchMesh mesh = verify::patchesOf(triangles);
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    HierarchySettings coarse;  // links high in the tree
    coarse.linkTolerance = 1e-3;
    const auto transport = build(mesh, system, coarse);
    ASSERT_TRUE(transport);
    ASSERT_GT(transport->farLinks().others.size(), 0u);
    const std::size_t n = mesh.patchCount(), m = 2;
    std::vector<uint8_t> sources(n, 0), receivers(n, 0);
    std::vector<double> radiosity(n * m), masked(n * m, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        sources[i] = i % 7 == 0 || (i >= 72 && i < 90);  // scattered, and part of a wall
        receivers[i] = i % 3 != 0;
        for (std::size_t c = 0; c < m; ++c) {
            radiosity[i * m + c] = 1 + 0.01 * double(i) + double(c);
            if (sources[i]) masked[i * m + c] = radiosity[i * m + c];
        }
    }
    std::vector<double> expected(n * m), got(n * m, -1.0);
    transport->gather(masked, m, expected);
    transport->gatherFrom(sources, receivers, radiosity, m, got);
    int compared = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t c = 0; c < m; ++c) {
            if (!receivers[i]) {
                ASSERT_EQ(got[i * m + c], -1.0) << "patch " << i;
                continue;
            }
            ASSERT_NEAR(got[i * m + c], expected[i * m + c], 1e-12 + 1e-9 * expected[i * m + c])
                << "patch " << i;
            compared += expected[i * m + c] > 0;
        }
    }
    EXPECT_GT(compared, int(n));
}

// A transport restored from parts (what the links cache stores) holds them to the tree: the
// same parts give the same gather; a far link whose source slot lies past the last node, or
// at a node that is not planar while the link is stored as planar, is refused, so a damaged
// entry with a valid checksum cannot make the gather read outside its values.
TEST(HierarchicalTransport, RestoredFarLinksMustPointAtTheirKindOfNode) {
    const PatchMesh mesh = verify::patchesOf(verify::parallelSquares(8, 1));
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    const auto built = build(mesh, system);
    ASSERT_TRUE(built);
    ASSERT_GT(built->farLinks().planarSlots.size(), 0u);
    const auto partsOf = [&](const HierarchicalTransport& t) {
        return HierarchicalParts{t.tree(),      t.near(),
                                 t.linkStats(), t.farLinks(),
                                 t.farScale(),  {t.rowSums().begin(), t.rowSums().end()},
                                 t.exposure()};
    };
    const HierarchicalTransport same(mesh, partsOf(*built));
    EXPECT_EQ(same.checkStructure(), "");
    const std::vector<double> ones(mesh.patchCount(), 1.0);
    std::vector<double> a(mesh.patchCount()), b(mesh.patchCount());
    built->gather(ones, 1, a);
    same.gather(ones, 1, b);
    EXPECT_EQ(a, b);
    // The root holds both squares, facing opposite ways: not planar.
    ASSERT_FALSE(built->tree().nodes[0].isPlanar());
    for (const uint64_t slot : {built->slots().back(), built->slots()[0]}) {
        HierarchicalParts parts = partsOf(*built);
        parts.far.planarSlots[0] = uint32_t(slot);
        const HierarchicalTransport damaged(mesh, std::move(parts));
        EXPECT_NE(damaged.checkStructure().find("planar far link 0 has slot"), std::string::npos)
            << damaged.checkStructure();
    }
}

// The build reports its two stages, the refinement ("links") and the near factors, each ending
// at its total, to the observer a front end draws its progress bar from (the viewer's).
TEST(HierarchicalTransport, TheBuildReportsItsProgress) {
    SessionSettings settings = cornellSettings(0.15);
    settings.transport = TransportKind::Hierarchical;
    auto session = Session::open(settings);
    ASSERT_TRUE(session.ok()) << session.error().message;
    std::mutex mutex;
    std::map<std::string, std::pair<uint64_t, uint64_t>> last;  // stage: done, total
    ASSERT_TRUE(session
                    ->buildFormFactors(nullptr,
                                       [&](std::string_view stage, uint64_t done, uint64_t total) {
                                           const std::lock_guard lock(mutex);
                                           auto& entry = last[std::string(stage)];
                                           EXPECT_GE(done, entry.first) << stage;
                                           entry = {done, total};
                                       })
                    .ok());
    ASSERT_EQ(last.size(), 2u);
    for (const char* stage : {"links", "near factors"}) {
        ASSERT_TRUE(last.count(stage)) << stage;
        EXPECT_GT(last[stage].second, 0u) << stage;
        EXPECT_EQ(last[stage].first, last[stage].second) << stage;
    }
}

// The build's record limit holds exactly: given the memory for the records an unlimited build
// makes (linkRecordLimit: the tree's arrays and the records three times over), it builds the
// same links; given one record byte less, it stops with kLinkRecordsOverLimit.
TEST(HierarchicalTransport, TheBuildStopsExactlyWhenItsRecordsPassTheLimit) {
    const PatchMesh mesh = verify::patchesOf(verify::parallelSquares(16, 1));
    const RadiositySystem system = greySystem(mesh, 0.5, 1);
    auto exposure = patchExposure(mesh);
    ASSERT_TRUE(exposure.ok()) << exposure.error().message;
    const auto unlimited = build(mesh, system);
    ASSERT_TRUE(unlimited);
    const LinkStats& stats = unlimited->linkStats();
    const uint64_t records =
        stats.farLinks * kFarRecordBytes + stats.nearPairsEvaluated * kNearRecordBytes;
    ASSERT_GT(records, 0u);
    // The tree's share: maxBytes - 3 x the limit, where 3 divides maxBytes less the tree.
    uint64_t tree = UINT64_MAX;
    for (uint64_t max = uint64_t(1) << 40; max < (uint64_t(1) << 40) + 3; ++max)
        tree = std::min(tree, max - 3 * linkRecordLimit(mesh, 1, max));
    const uint64_t exact = tree + 3 * records;
    ASSERT_EQ(linkRecordLimit(mesh, 1, exact), records);
    ASSERT_EQ(linkRecordLimit(mesh, 1, exact - 1), records - 1);
    auto fits = buildHierarchicalTransport(mesh, *exposure, system, {}, quietSettings(), exact);
    ASSERT_TRUE(fits.ok()) << fits.error().message;
    EXPECT_EQ((*fits)->linkStats().farLinks, stats.farLinks);
    EXPECT_EQ((*fits)->linkStats().nearEntries, stats.nearEntries);
    auto over = buildHierarchicalTransport(mesh, *exposure, system, {}, quietSettings(), exact - 1);
    ASSERT_FALSE(over.ok());
    EXPECT_TRUE(over.error().message.starts_with(kLinkRecordsOverLimit)) << over.error().message;
    EXPECT_EQ(linkRecordLimit(mesh, 1, tree), 0u);
}

// An edit that moves light (the red wall made a lamp as strong as the ceiling's) leaves links
// refined for the old light too coarse around it: the session says so, and refines them again
// to exactly the links a fresh session with the edited material builds (the same B bit for
// bit). Making every light three times as strong moves none: no refinement is asked for.
TEST(HierarchicalTransport, AnEditThatMovesLightRefinesTheLinksAgain) {
    SessionSettings settings = cornellSettings(0.15);
    settings.transport = TransportKind::Hierarchical;
    auto session = Session::open(settings);
    ASSERT_TRUE(session.ok()) << session.error().message;
    ASSERT_TRUE(session->buildFormFactors().ok());
    EXPECT_FALSE(session->linksOutdated());
    constexpr std::size_t kRed = 1, kEmitter = 3;
    ASSERT_EQ(session->scene().materials[kEmitter].name, "emitter");
    Material stronger = session->scene().materials[kEmitter];
    stronger.spectral.emission->scale *= 3;
    ASSERT_TRUE(session->setMaterial(kEmitter, stronger).ok());
    EXPECT_FALSE(session->linksOutdated());

    Material lamp = session->scene().materials[kRed];
    lamp.spectral.emission = stronger.spectral.emission;
    ASSERT_TRUE(session->setMaterial(kRed, lamp).ok());
    EXPECT_TRUE(session->linksOutdated());
    const uint64_t linksBefore = session->transport().stats().entries;
    auto refined = session->refineLinks();
    ASSERT_TRUE(refined.ok()) << refined.error().message;
    EXPECT_FALSE(session->linksOutdated());
    EXPECT_NE(session->transport().stats().entries, linksBefore);
    auto solved = session->solve();
    ASSERT_TRUE(solved.ok()) << solved.error().message;

    auto fresh = Session::open(settings);
    ASSERT_TRUE(fresh.ok()) << fresh.error().message;
    ASSERT_TRUE(fresh->setMaterial(kEmitter, stronger).ok());
    ASSERT_TRUE(fresh->setMaterial(kRed, lamp).ok());
    ASSERT_TRUE(fresh->buildFormFactors().ok());
    EXPECT_EQ(fresh->transport().stats().entries, session->transport().stats().entries);
    const auto* ours = dynamic_cast<const HierarchicalTransport*>(&session->transport());
    const auto* theirs = dynamic_cast<const HierarchicalTransport*>(&fresh->transport());
    ASSERT_TRUE(ours && theirs);
    auto expected = theirs->solve(fresh->system(), SolverSettings{});
    auto got = ours->solve(session->system(), SolverSettings{});
    ASSERT_TRUE(expected.ok() && got.ok());
    EXPECT_EQ(got->radiosity, expected->radiosity);
}

// Per patch: its near factors plus the far half-links of its leaf and of every ancestor (the
// links whose transport reaches it); {mean, largest}.
std::pair<double, uint64_t> linksPerPatch(const HierarchicalTransport& transport) {
    const ClusterTree& tree = transport.tree();
    std::vector<uint64_t> inherited(tree.nodes.size(), 0);
    uint64_t most = 0, total = 0;
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
        const HierarchyNode& node = tree.nodes[k];
        inherited[k] += transport.farLinks().count(k);
        if (!node.isLeaf()) {
            for (uint32_t child : node.children)
                inherited[child] = inherited[k];
            continue;
        }
        const uint64_t count = inherited[k] + transport.near().rowLength(tree.order[node.first]);
        most = std::max(most, count);
        total += count;
    }
    return {double(total) / double(tree.order.size()), most};
}

// The Cornell box at 3,656 patches: patch radiosity within 1% (RMS over the area, relative to
// the mean) of the matrix path's, with under half its stored factors; each far link serves both
// directions with one coupling (reciprocity A_R F_RS = A_S F_SR per link); no row sums past 1.
TEST(HierarchicalTransport, CornellBoxMatchesTheMatrixPath) {
    auto session = Session::open(cornellSettings(0.05));
    ASSERT_TRUE(session.ok()) << session.error().message;
    ASSERT_TRUE(session->buildFormFactors().ok());
    const RadiositySystem& system = session->system();
    const PatchMesh& mesh = session->patches();
    SolverSettings solver;
    solver.tolerance = 1e-7;
    auto matrix = session->transport().solve(system, solver);
    ASSERT_TRUE(matrix.ok());
    const auto transport = build(mesh, system);
    ASSERT_TRUE(transport);
    auto solved = transport->solve(system, solver);
    ASSERT_TRUE(solved.ok()) << solved.error().message;

    const std::size_t n = system.patchCount, m = system.wavelengthCount;
    double sumSq = 0, sum = 0, area = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double a = 0, b = 0;
        for (std::size_t k = 0; k < m; ++k) {
            a += solved->radiosity[i * m + k] * system.binWidthsNm[k];
            b += matrix->radiosity[i * m + k] * system.binWidthsNm[k];
        }
        sumSq += mesh.areas[i] * (a - b) * (a - b);
        sum += mesh.areas[i] * b;
        area += mesh.areas[i];
    }
    EXPECT_LT(std::sqrt(sumSq / area) / (sum / area), 0.01);
    EXPECT_LT(transport->stats().entries, session->transport().stats().entries / 2);

    // Each half-link's other half, under its source, with the same weight (between two planar
    // nodes, -K (u . n_S) (u . n_R) both ways) or the same vector (negated between two other
    // nodes: sqrt(K) u, u reversed), to float rounding.
    const std::vector<uint64_t>& slots = transport->slots();
    const FarHalfLinks& far = transport->farLinks();
    const auto nodeAt = [&slots](uint32_t slot) {
        return uint32_t(std::lower_bound(slots.begin(), slots.end(), uint64_t(slot)) -
                        slots.begin());
    };
    const auto planar = [&](std::size_t node) {
        return transport->tree().nodes[node].isLeaf() || transport->tree().nodes[node].isPlanar();
    };
    uint64_t halves = 0;
    for (std::size_t r = 0; r < transport->tree().nodes.size(); ++r) {
        const uint32_t back = uint32_t(slots[r]);
        for (uint64_t e = far.planarOffsets[r]; e < far.planarOffsets[r + 1]; ++e) {
            const uint32_t s = nodeAt(far.planarSlots[e]);
            const auto begin = far.planarSlots.begin() + std::ptrdiff_t(far.planarOffsets[s]);
            const auto end = far.planarSlots.begin() + std::ptrdiff_t(far.planarOffsets[s + 1]);
            const auto other = std::lower_bound(begin, end, back);
            ASSERT_TRUE(other != end && *other == back) << "node " << r << " and " << s;
            const float w = far.planarWeights[std::size_t(other - far.planarSlots.begin())];
            ASSERT_NEAR(w, far.planarWeights[e], 1e-6 * std::abs(w));
            ++halves;
        }
        for (uint64_t e = far.otherOffsets[r]; e < far.otherOffsets[r + 1]; ++e) {
            const FarHalfLinks::OtherLink& link = far.others[e];
            const uint32_t s = nodeAt(link.source());
            const auto begin = far.others.begin() + std::ptrdiff_t(far.otherOffsets[s]);
            const auto end = far.others.begin() + std::ptrdiff_t(far.otherOffsets[s + 1]);
            const auto other = std::find_if(begin, end, [back](const FarHalfLinks::OtherLink& l) {
                return l.source() == back;
            });
            ASSERT_TRUE(other != end) << "node " << r << " and " << s;
            const float sign = planar(r) || planar(s) ? 1.0f : -1.0f;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(other->v[c], sign * link.v[c], 1e-6 * std::abs(link.v[c]) + 1e-12);
            ++halves;
        }
    }
    EXPECT_EQ(halves, 2 * transport->linkStats().farLinks);
    // The summed factors leaving each patch, as the gather applies them (B = 1), and as stored.
    const std::vector<double> ones(n, 1.0);
    std::vector<double> sums(n);
    transport->gather(ones, 1, sums);
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_LE(sums[i], 1.0 + 1e-3) << "patch " << i;
        ASSERT_NEAR(sums[i], transport->rowSums()[i], 1e-6) << "patch " << i;
    }
}

// The same box at 920 and 3,656 patches (4x): the links reaching a patch grow slower than the
// patches on average (measured 424 -> 867, as n^0.52; an all-pairs row grows as n).
TEST(HierarchicalTransport, LinksPerPatchGrowFarSlowerThanThePatches) {
    std::pair<double, uint64_t> counts[2];
    std::size_t patches[2];
    for (int k = 0; k < 2; ++k) {
        auto session = Session::open(cornellSettings(k == 0 ? 0.1 : 0.05));
        ASSERT_TRUE(session.ok()) << session.error().message;
        const auto transport = build(session->patches(), session->system());
        ASSERT_TRUE(transport);
        counts[k] = linksPerPatch(*transport);
        patches[k] = session->patches().patchCount();
    }
    const double growth = double(patches[1]) / double(patches[0]);
    EXPECT_LT(counts[1].first / counts[0].first, std::pow(growth, 0.7));
    // The largest is not yet bounded (measured 624 -> 2,044: as n^0.86, docs/hierarchical.md);
    // it stays under the matrix path's largest row, which is every patch the row sees.
    EXPECT_LT(counts[1].second, patches[1]);
}

}  // namespace
}  // namespace daisy
