// The first bounce of an edit (Session::previewBounce): B = E + M G with the last finished
// solve's G, on the exposed parts the solve uses (radiosity/exposed_system.h). Oracles: a
// converged solve is its own fixed point, so the preview of an unedited scene must reproduce it;
// after an edit, a fully exposed patch's preview is E + rho' G exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/cancel.h"
#include "pipeline/session.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

// The white furnace with a box standing on its floor, on one wavelength, solved to 1e-9.
Session solvedFurnaceWithABox() {
    SessionSettings settings;
    settings.subdivideMaxEdge = 0;
    settings.wavelengthsText = "550";
    settings.wavelengthSet = *WavelengthSet::fromWavelengths({550}, "550");
    settings.solver.tolerance = 1e-9;
    settings.logStages = false;
    auto session = Session::fromScene(verify::furnaceWithABoxOnItsFloor(), settings);
    EXPECT_TRUE(session.ok()) << session.error().message;
    auto solved = session->solve();
    EXPECT_TRUE(solved.ok() && solved->converged);
    return std::move(*session);
}

// On the converged furnace the preview of every patch is the solution itself, partly buried
// floor patches included: the bounce runs on the exposed parts (B' = E + s M G, then
// B = E + phi (B' - E)) as the solve did. A whole-patch bounce E + M G is off there by the
// factor phi s on the reflected part, which the second half checks is a real difference.
TEST(SessionPreview, PreviewOfTheConvergedSolveIsTheSolveOnPartlyBuriedPatches) {
    Session session = solvedFurnaceWithABox();
    const std::vector<double> converged = session.solution().radiosity;
    const std::vector<double> gathered = session.lastGathered();
    ASSERT_EQ(gathered.size(), converged.size());
    auto exposure = session.exposure();
    ASSERT_TRUE(exposure.ok());
    const std::vector<float>& phi = (*exposure)->fraction;
    const std::span<const double> rows = session.transport().rowSums();

    std::vector<uint8_t> all(converged.size(), 1);
    ASSERT_TRUE(session.previewBounce(all));
    const std::vector<double>& preview = session.solution().radiosity;
    int partly = 0;
    double worst = 0, wholePatchWorst = 0;
    for (std::size_t i = 0; i < converged.size(); ++i) {
        if (rows[i] < 1e-3) continue;  // the box's bottom sees nothing
        worst = std::max(worst, std::abs(preview[i] - converged[i]) / converged[i]);
        if (phi[i] > 0 && phi[i] < 1) {
            ++partly;
            const double wholePatch = 1 + 0.5 * gathered[i];  // E + rho G
            wholePatchWorst =
                std::max(wholePatchWorst, std::abs(wholePatch - converged[i]) / converged[i]);
        }
    }
    EXPECT_GT(partly, 20);
    EXPECT_LT(worst, 1e-7);  // the solve's residual, 1e-9, amplified by 1 / (1 - rho)
    EXPECT_GT(wholePatchWorst, 0.05);
}

// After an edit (rho 0.5 -> 0.2) the preview of a fully exposed patch is E + 0.2 G with the G
// of the last finished solve, and the patches not selected keep their solved B.
TEST(SessionPreview, EditedMaterialGetsOneBounceOfTheLastGather) {
    Session session = solvedFurnaceWithABox();
    const std::vector<double> converged = session.solution().radiosity;
    const std::vector<double> gathered = session.lastGathered();
    auto exposure = session.exposure();
    ASSERT_TRUE(exposure.ok());
    const std::vector<float>& phi = (*exposure)->fraction;
    ASSERT_TRUE(session.setMaterial(0, verify::flatMaterial("flat", 0.2, 1)).ok());
    std::vector<uint8_t> selected(converged.size(), 0);
    for (std::size_t i = 0; i < selected.size(); i += 2)
        selected[i] = 1;
    ASSERT_TRUE(session.previewBounce(selected));
    const std::vector<double>& preview = session.solution().radiosity;
    int checked = 0;
    for (std::size_t i = 0; i < selected.size(); ++i) {
        if (!selected[i]) {
            EXPECT_EQ(preview[i], converged[i]) << i;
        } else if (phi[i] == 1) {
            EXPECT_NEAR(preview[i], 1 + 0.2 * gathered[i], 1e-12) << i;
            ++checked;
        }
    }
    EXPECT_GT(checked, 100);
}

// A cancelled solve leaves the last finished solve's G in place: a preview never bounces the
// partial gather of an interrupted sweep.
TEST(SessionPreview, CancelledSolveKeepsTheLastFinishedGather) {
    Session session = solvedFurnaceWithABox();
    const std::vector<double> gathered = session.lastGathered();
    ASSERT_TRUE(session.setMaterial(0, verify::flatMaterial("flat", 0.3, 1)).ok());
    CancelToken cancel;
    cancel.cancel();
    SolveRequest request;
    request.cancel = &cancel;
    auto solved = session.solve(request);
    ASSERT_TRUE(solved.ok()) << solved.error().message;
    EXPECT_TRUE(solved->cancelled);
    EXPECT_EQ(session.lastGathered(), gathered);
}

// Before any solve there is no gather to bounce: the preview says so and changes nothing.
TEST(SessionPreview, NoPreviewBeforeTheFirstSolve) {
    SessionSettings settings;
    settings.subdivideMaxEdge = 0;
    settings.wavelengthSet = *WavelengthSet::fromWavelengths({550}, "550");
    settings.logStages = false;
    auto session = Session::fromScene(verify::furnaceWithABoxOnItsFloor(), settings);
    ASSERT_TRUE(session.ok());
    ASSERT_TRUE(session->buildFormFactors().ok());
    std::vector<uint8_t> all(session->patches().patchCount(), 1);
    EXPECT_FALSE(session->previewBounce(all));
    EXPECT_FALSE(session->hasSolution());
}

}  // namespace
}  // namespace daisy
