// Accuracy of the view-factor methods against closed forms and conservation laws, as the
// Markdown table in docs/formfactors.md. Oracles: Howell's catalogue C-11 (parallel unit squares
// at distance 1: 0.199824895698) and C-14 (perpendicular unit squares sharing an edge:
// 0.200043776075); the summation rule in a closed unit cube (every row of F sums to 1); a plate
// halfway between two squares at distance 2 that hides exactly half (F = C-11(X = Y = 0.5) / 2
// = 0.0342947944). Usage: formfactor_accuracy [--threads T]; prints the table on stdout.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/timer.h"
#include "radiosity/form_factors.h"
#include "radiosity/matrix_transport.h"
#include "raycast/ray_caster.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

using namespace daisy;

namespace {

using verify::kHowellC11;
using verify::kHowellC14;
constexpr double kHalfHidden = 0.5 * verify::kHowellC11Distance2;

struct Run {
    std::shared_ptr<const Transport> f;
    PatchMesh mesh;
    double seconds = 0;
};

Run run(const TriangleMesh& triangles, const FormFactorSettings& settings) {
    Run r;
    r.mesh = verify::patchesOf(triangles);
    auto caster = makeRayCaster(r.mesh);
    const Timer timer;
    auto result = computeFormFactors(r.mesh, settings, **caster);
    r.seconds = timer.seconds();
    r.f = std::make_shared<MatrixTransport>(std::move(result->matrix));
    return r;
}

// Area-weighted factor from the first `count` patches to the next `count`.
double groupFactor(const Run& r, uint32_t count) {
    return verify::groupFactor(r.mesh, *r.f, 0, count, count, 2 * count);
}

double squares(const FormFactorSettings& settings, int n, bool perpendicular) {
    const TriangleMesh mesh =
        perpendicular ? verify::perpendicularSquares(n) : verify::parallelSquares(n);
    const double exact = perpendicular ? kHowellC14 : kHowellC11;
    return groupFactor(run(mesh, settings), uint32_t(2 * n * n)) / exact - 1;
}

// Largest |row sum - 1| in the unit cube room with n x n quads a face, and the build time.
std::pair<double, double> cube(const FormFactorSettings& settings, int n) {
    const Run r = run(verify::unitCubeRoom(n), settings);
    double worst = 0;
    for (double sum : r.f->rowSums())
        worst = std::max(worst, std::fabs(sum - 1));
    return {worst, r.seconds};
}

double halfHidden(const FormFactorSettings& settings) {
    return groupFactor(run(verify::halfOccludedSquares(), settings), 128) / kHalfHidden - 1;
}

}  // namespace

int main(int argc, char** argv) {
    FormFactorSettings base;
    base.progress = false;
    for (int a = 1; a + 1 < argc; ++a) {
        if (std::strcmp(argv[a], "--threads") == 0) base.threads = std::atoi(argv[a + 1]);
    }
    struct Setting {
        FormFactorMethod method;
        int level, rays, stochasticRays;
    };
    const std::vector<Setting> settings = {
        {FormFactorMethod::Riemann, 0, 16, 0},       {FormFactorMethod::Riemann, 1, 16, 0},
        {FormFactorMethod::Riemann, 2, 16, 0},       {FormFactorMethod::Riemann, 3, 16, 0},
        {FormFactorMethod::Nusselt, 0, 16, 0},       {FormFactorMethod::Hybrid, 0, 16, 0},
        {FormFactorMethod::Hybrid, 1, 16, 0},        {FormFactorMethod::Hybrid, 2, 16, 0},
        {FormFactorMethod::Hybrid, 1, 1, 0},         {FormFactorMethod::Hybrid, 1, 4, 0},
        {FormFactorMethod::Hybrid, 1, 64, 0},        {FormFactorMethod::Stochastic, 0, 0, 256},
        {FormFactorMethod::Stochastic, 0, 0, 1024},  {FormFactorMethod::Stochastic, 0, 0, 4096},
        {FormFactorMethod::Stochastic, 0, 0, 16384},
    };
    std::printf(
        "| method | L | K | N | C-11, 2 tri | C-11, 32 tri | C-14, 2 tri | C-14, 32 tri | "
        "cube 2x2 max abs(row-1) | cube 6x6 max abs(row-1) | half hidden | cube 6x6 time |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Setting& s : settings) {
        FormFactorSettings f = base;
        f.method = s.method;
        f.quadratureLevel = s.level;
        f.raysPerPair = s.rays;
        f.stochasticRays = std::max(1, s.stochasticRays);
        const bool stochastic = s.method == FormFactorMethod::Stochastic;
        const auto [coarse, coarseSeconds] = cube(f, 2);
        const auto [fine, fineSeconds] = cube(f, 6);
        (void)coarseSeconds;
        std::printf(
            "| %s | %s | %s | %s | %+.1e | %+.1e | %+.1e | %+.1e | %.1e | %.1e | %+.1e | "
            "%.0f ms |\n",
            formFactorMethodName(s.method),
            stochastic || s.method == FormFactorMethod::Nusselt ? "-"
                                                                : std::to_string(s.level).c_str(),
            stochastic ? "-" : std::to_string(s.rays).c_str(),
            stochastic ? std::to_string(s.stochasticRays).c_str() : "-", squares(f, 1, false),
            squares(f, 4, false), squares(f, 1, true), squares(f, 4, true), coarse, fine,
            halfHidden(f), 1e3 * fineSeconds);
    }
    return 0;
}
