// spectral_report: measures what the wavelength presets and the RGB -> spectrum table cost in
// colour accuracy, for docs/spectral.md. Writes three CSV files (plotted by
// tools/plot_spectral.py) and prints a Markdown summary.
//
// Usage: spectral_report [--out-dir DIR] [--resolutions 9,17,25,33,49,65]
//   DIR defaults to docs/images of this source tree.
//
// Every measurement is the renderer's path for a diffuse surface under D65 (round_trip.h):
// linear sRGB -> reflectance spectrum -> samples on the set -> XYZ under D65 sampled on the same
// set -> linear sRGB, without white balance unless a column says so. Delta E*ab is CIE 1976
// against the input colour, with the IEC 61966-2-1 D65 white as the reference white.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/strings.h"
#include "spectral/colorchecker.h"
#include "spectral/rgb_upsampling_fit.h"
#include "spectral/round_trip.h"

namespace {

using namespace daisy;

constexpr int kRandomColours = 10000;
constexpr std::uint64_t kSeed = 2019;

struct Measured {
    Rgb rgb;  // the round trip's linear sRGB
    double deltaE = 0;  // raw, against the input
    double deltaEBalanced = 0;  // after Bradford adaptation of the set's white to D65
    double maxAbs = 0;  // max |rgb - input| in linear sRGB
};

class Meter {
public:
    explicit Meter(const WavelengthSet& set)
        : set_(set),
          roundTrip_(set),
          setWhite_(roundTrip_.whiteXyz()),
          d65White_(linearSrgbToXyz({1, 1, 1})) {}

    Measured operator()(const Rgb& input) const {
        Measured m;
        const Xyz xyz = roundTrip_.xyz(input);
        m.rgb = xyzToLinearSrgb(xyz);
        const Lab goal = xyzToLab(linearSrgbToXyz(input), d65White_);
        m.deltaE = deltaE76(xyzToLab(xyz, d65White_), goal);
        m.deltaEBalanced =
            deltaE76(xyzToLab(adaptXyzBradford(xyz, setWhite_, d65White_), d65White_), goal);
        for (int c = 0; c < 3; ++c)
            m.maxAbs = std::max(m.maxAbs, std::abs(m.rgb[c] - input[c]));
        return m;
    }

    const WavelengthSet& set() const { return set_; }
    const Xyz& setWhite() const { return setWhite_; }

private:
    WavelengthSet set_;
    ReflectanceRoundTrip roundTrip_;
    Xyz setWhite_, d65White_;
};

double quantile(std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    const std::size_t index = std::min(values.size() - 1, std::size_t(q * double(values.size())));
    return values[index];
}

double mean(const std::vector<double>& values) {
    double sum = 0;
    for (double v : values)
        sum += v;
    return sum / double(values.size());
}

std::vector<Rgb> randomColours() {
    SplitMix64 random(kSeed);
    std::vector<Rgb> colours(kRandomColours);
    for (Rgb& c : colours)
        c = {random.uniform(), random.uniform(), random.uniform()};
    return colours;
}

std::vector<int> parseResolutions(const std::string& text) {
    std::vector<int> out;
    std::istringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
        out.push_back(std::atoi(item.c_str()));
    return out;
}

void presetReport(const std::filesystem::path& outDir) {
    const std::vector<WavelengthSet> sets = {daisyriotWavelengths(), meyer4Wavelengths(),
                                             visibleWavelengths(), fineWavelengths()};
    std::vector<Meter> meters;
    for (const WavelengthSet& set : sets)
        meters.emplace_back(set);
    const Meter& fine = meters.back();

    std::ofstream patches(outDir / "spectral_error.csv");
    patches << "preset,samples,patch,srgb8_r,srgb8_g,srgb8_b,r,g,b,r_out,g_out,b_out,max_abs,"
               "delta_e,delta_e_balanced,delta_e_vs_fine\n";
    std::ofstream quantiles(outDir / "spectral_random_quantiles.csv");
    quantiles << "preset,quantile,delta_e,delta_e_balanced,max_abs\n";

    std::cout << "| preset | samples | white x, y | ColorChecker dE*ab mean / max | "
                 "balanced mean / max | vs fine max | max abs RGB | random dE*ab median / "
                 "p99 / max | random max abs RGB |\n|---|---|---|---|---|---|---|---|---|\n";
    const std::vector<Rgb> random = randomColours();
    for (const Meter& meter : meters) {
        std::vector<double> deltaE, balanced, vsFine, maxAbs;
        for (const ColorCheckerPatch& patch : kColorChecker) {
            const Rgb input = colorCheckerLinear(patch);
            const Measured m = meter(input);
            const Measured reference = fine(input);
            const Xyz white = linearSrgbToXyz({1, 1, 1});
            const double toFine = deltaE76(xyzToLab(linearSrgbToXyz(m.rgb), white),
                                           xyzToLab(linearSrgbToXyz(reference.rgb), white));
            deltaE.push_back(m.deltaE);
            balanced.push_back(m.deltaEBalanced);
            vsFine.push_back(toFine);
            maxAbs.push_back(m.maxAbs);
            patches << meter.set().name() << ',' << meter.set().size() << ",\"" << patch.name
                    << "\"," << patch.srgb8[0] << ',' << patch.srgb8[1] << ',' << patch.srgb8[2];
            for (double v : {input[0], input[1], input[2], m.rgb[0], m.rgb[1], m.rgb[2], m.maxAbs,
                             m.deltaE, m.deltaEBalanced, toFine})
                patches << ',' << formatNumber(v, 6);
            patches << '\n';
        }
        std::vector<double> randomDeltaE, randomBalanced, randomAbs;
        for (const Rgb& input : random) {
            const Measured m = meter(input);
            randomDeltaE.push_back(m.deltaE);
            randomBalanced.push_back(m.deltaEBalanced);
            randomAbs.push_back(m.maxAbs);
        }
        for (int q = 0; q <= 100; ++q) {
            quantiles << meter.set().name() << ',' << q / 100.0 << ','
                      << formatNumber(quantile(randomDeltaE, q / 100.0), 6) << ','
                      << formatNumber(quantile(randomBalanced, q / 100.0), 6) << ','
                      << formatNumber(quantile(randomAbs, q / 100.0), 6) << '\n';
        }
        const auto xy = xyzToXy(meter.setWhite());
        const auto f = [](double v) { return formatNumber(v, 3); };
        std::cout << "| " << meter.set().name() << " | " << meter.set().size() << " | "
                  << formatNumber(xy[0], 5) << ", " << formatNumber(xy[1], 5) << " | "
                  << f(mean(deltaE)) << " / " << f(quantile(deltaE, 1)) << " | "
                  << f(mean(balanced)) << " / " << f(quantile(balanced, 1)) << " | "
                  << f(quantile(vsFine, 1)) << " | " << f(quantile(maxAbs, 1)) << " | "
                  << f(quantile(randomDeltaE, 0.5)) << " / " << f(quantile(randomDeltaE, 0.99))
                  << " / " << f(quantile(randomDeltaE, 1)) << " | " << f(quantile(randomAbs, 1))
                  << " |\n";
    }
}

void resolutionReport(const std::filesystem::path& outDir, const std::vector<int>& resolutions) {
    // Table quality measured with the fit's own 1 nm colorimetry (no wavelength set), so only
    // the table's interpolation (or the polish) is seen.
    const SigmoidFitter fitter;
    const std::vector<Rgb> random = randomColours();
    std::ofstream csv(outDir / "spectral_table_resolution.csv");
    csv << "resolution,fit_seconds,coefficients,lookup_max,lookup_p99,lookup_median,"
           "polished_max,polished_median\n";
    std::cout << "\n| resolution | fit time (s) | table size | lookup max / p99 / median | "
                 "lookup + polish max / median |\n|---|---|---|---|---|\n";
    for (int resolution : resolutions) {
        RgbTableFitStats stats;
        const RgbToSpectrumTable table = fitRgbToSpectrumTable(resolution, &stats);
        std::vector<double> lookup, polished;
        for (const Rgb& input : random) {
            const Rgb a = xyzToLinearSrgb(fitter.reflectanceXyz(table.lookup(input)));
            const Rgb b = xyzToLinearSrgb(fitter.reflectanceXyz(rgbToReflectance(input, table)));
            double ea = 0, eb = 0;
            for (int c = 0; c < 3; ++c) {
                ea = std::max(ea, std::abs(a[c] - input[c]));
                eb = std::max(eb, std::abs(b[c] - input[c]));
            }
            lookup.push_back(ea);
            polished.push_back(eb);
        }
        const auto f = [](double v) { return formatNumber(v, 3); };
        csv << resolution << ',' << f(stats.seconds) << ',' << table.coefficients().size() << ','
            << f(quantile(lookup, 1)) << ',' << f(quantile(lookup, 0.99)) << ','
            << f(quantile(lookup, 0.5)) << ',' << f(quantile(polished, 1)) << ','
            << f(quantile(polished, 0.5)) << '\n';
        std::cout << "| " << resolution << " | " << f(stats.seconds) << " | "
                  << formatCount(table.coefficients().size()) << " floats | "
                  << f(quantile(lookup, 1)) << " / " << f(quantile(lookup, 0.99)) << " / "
                  << f(quantile(lookup, 0.5)) << " | " << f(quantile(polished, 1)) << " / "
                  << f(quantile(polished, 0.5)) << " |\n";
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::filesystem::path outDir =
        std::filesystem::path(__FILE__).parent_path().parent_path() / "docs" / "images";
    std::vector<int> resolutions = {9, 17, 25, 33, 49, 65};
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--out-dir" && i + 1 < argc) {
            outDir = argv[++i];
        } else if (arg == "--resolutions" && i + 1 < argc) {
            resolutions = parseResolutions(argv[++i]);
        } else {
            std::cerr << "usage: spectral_report [--out-dir DIR] [--resolutions 9,17,33]\n";
            return 2;
        }
    }
    for (int resolution : resolutions) {
        if (resolution < 2 || resolution > 256) {
            std::cerr << "spectral_report: resolutions must be 2..256\n";
            return 2;
        }
    }
    std::filesystem::create_directories(outDir);
    presetReport(outDir);
    resolutionReport(outDir, resolutions);
    std::cerr << "wrote " << (outDir / "spectral_error.csv").string() << ", "
              << (outDir / "spectral_random_quantiles.csv").string() << ", "
              << (outDir / "spectral_table_resolution.csv").string() << "\n";
    return 0;
}
