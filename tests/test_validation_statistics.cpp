// The mathematics of `carom validate` (app/validate/statistics.h) on inputs
// with known answers.
#include <cmath>
#include <random>
#include <vector>

#include <carom/types.h>
#include <doctest/doctest.h>

#include "app/validate/statistics.h"
#include "engine/scene.h"

using namespace carom;
using namespace carom::validation;

namespace {

// The speed whose Rayleigh CDF is p.
double rayleighQuantile(double p, double kTOverMass) { return std::sqrt(-2.0 * kTOverMass * std::log1p(-p)); }

// n speeds at the quantiles (i + 1/2) / n: as close to Rayleigh as n samples can be.
std::vector<double> rayleighQuantiles(std::size_t n, double kTOverMass) {
    std::vector<double> speeds;
    for (std::size_t i = 0; i < n; ++i) speeds.push_back(rayleighQuantile((i + 0.5) / double(n), kTOverMass));
    return speeds;
}

}  // namespace

TEST_CASE("blockAverage: mean and standard error of the block means") {
    const MeanAndError m = blockAverage({1.0, 2.0, 3.0, 4.0});
    CHECK(m.mean == doctest::Approx(2.5));
    CHECK(m.error == doctest::Approx(std::sqrt((5.0 / 3.0) / 4.0)));  // sample variance 5/3, four blocks
    CHECK(blockAverage({7.0}).error == 0.0);
    CHECK(blockAverage({}).mean == 0.0);
}

TEST_CASE("blockingAverage: the error of correlated block means") {
    std::mt19937_64 random(3);
    std::normal_distribution<double> normal(0.0, 1.0);
    SUBCASE("independent blocks: about the plain standard error, never less") {
        std::vector<double> values;
        for (int i = 0; i < 4096; ++i) values.push_back(normal(random));
        const MeanAndError plain = blockAverage(values), blocking = blockingAverage(values, 16);
        CHECK(blocking.mean == plain.mean);
        CHECK(blocking.error >= plain.error);
        // The largest of five estimates: 0.97 to 1.57 times 1/64 for 1000 seeds.
        CHECK(blocking.error > 0.9 / 64.0);
        CHECK(blocking.error < 1.7 / 64.0);
    }
    SUBCASE("blocks correlated as x_k = 0.8 x_(k-1) + noise: the true error, three times the plain one") {
        const double rho = 0.8;
        std::vector<double> values;
        double x = 0.0;
        for (int i = 0; i < 8192; ++i) values.push_back(x = rho * x + std::sqrt(1.0 - rho * rho) * normal(random));
        // Unit variance, so the plain error is 1/sqrt(n); correlation
        // multiplies it by sqrt((1 + rho) / (1 - rho)) = 3.
        const double exact = std::sqrt((1.0 + rho) / (1.0 - rho) / 8192.0);
        CHECK(blockAverage(values).error < 0.5 * exact);
        // 0.80 to 1.63 times the exact error for 1000 seeds.
        CHECK(blockingAverage(values, 16).error > 0.75 * exact);
        CHECK(blockingAverage(values, 16).error < 1.7 * exact);
    }
    SUBCASE("too few blocks to merge: the plain error") {
        CHECK(blockingAverage({1.0, 2.0, 3.0, 4.0}, 8).error == blockAverage({1.0, 2.0, 3.0, 4.0}).error);
        CHECK(blockingAverage({}, 8).mean == 0.0);
    }
}

TEST_CASE("Rayleigh distribution: CDF, density and KS statistic") {
    const double kT = 1.7;
    CHECK(rayleighCdf(0.0, kT) == 0.0);
    CHECK(rayleighCdf(rayleighQuantile(0.3, kT), kT) == doctest::Approx(0.3));
    // The density integrates to the CDF.
    double integral = 0.0;
    const double top = 2.0, step = 1e-4;
    for (double v = step / 2; v < top; v += step) integral += rayleighPdf(v, kT) * step;
    CHECK(integral == doctest::Approx(rayleighCdf(top, kT)).epsilon(1e-6));

    CHECK(ksCritical05(100) == doctest::Approx(0.1358));

    // Speeds at the exact quantiles miss the CDF by half a step, 1 / (2n).
    const std::size_t n = 1000;
    const double exact = ksRayleigh(rayleighQuantiles(n, kT), kT);
    CHECK(exact == doctest::Approx(0.5 / n));
    CHECK(exact < ksCritical05(n));

    // The same speeds tested against twice the temperature are far off.
    CHECK(ksRayleigh(rayleighQuantiles(n, kT), 2.0 * kT) > 5.0 * ksCritical05(n));
    // So is a uniform distribution of speeds.
    std::vector<double> uniform;
    for (std::size_t i = 0; i < n; ++i) uniform.push_back(3.0 * (i + 0.5) / double(n));
    CHECK(ksRayleigh(uniform, kT) > 2.0 * ksCritical05(n));
}

TEST_CASE("H-function: uniform square exactly, Gaussian within the estimator's bias") {
    SUBCASE("velocities evenly spread over [-a, a]^2 with bin edges at +-a: H = -ln(4 a^2)") {
        const double a = std::sqrt(3.0);
        std::vector<double> vx, vy;
        const int perAxis = 200;  // 25 points per bin along each axis
        for (int i = 0; i < perAxis; ++i)
            for (int j = 0; j < perAxis; ++j) {
                vx.push_back(-a + 2.0 * a * (i + 0.5) / perAxis);
                vy.push_back(-a + 2.0 * a * (j + 0.5) / perAxis);
            }
        const HEstimate h = hFunction(vx, vy, VelocityHistogram{3.0 * a, 24});
        CHECK(h.value == doctest::Approx(-std::log(4.0 * a * a)).epsilon(1e-9));
        CHECK(h.occupiedBins == 64);
        CHECK(h.outside == 0);
        // The relaxation's exact change of H: to the Gaussian of the same energy.
        CHECK(hEquilibrium(a * a / 3.0) - h.value == doctest::Approx(std::log(6.0 / kPi) - 1.0));
        CHECK(std::log(6.0 / kPi) - 1.0 == doctest::Approx(-0.3529).epsilon(1e-4));
    }
    SUBCASE("a Gaussian sample: H = ln(m / 2 pi kT) - 1 + plug-in bias - binning bias") {
        const double kT = 0.8;
        std::mt19937_64 random(5);
        std::normal_distribution<double> normal(0.0, std::sqrt(kT));
        std::vector<double> vx, vy;
        for (int i = 0; i < 400000; ++i) {
            vx.push_back(normal(random));
            vy.push_back(normal(random));
        }
        const VelocityHistogram histogram{6.0 * std::sqrt(kT), 48};
        const HEstimate h = hFunction(vx, vy, histogram);
        const double width = 2.0 * histogram.range / histogram.binsPerAxis;
        const double binning = width * width / (12.0 * kT);
        CHECK(h.bias() == doctest::Approx(double(h.occupiedBins - 1) / (2.0 * 400000)));
        // Within three standard errors of the estimate, 3 / sqrt(n) = 0.005.
        CHECK(std::abs(h.value - (hEquilibrium(kT) + h.bias() - binning)) < 0.005);
    }
}

TEST_CASE("leastSquaresLine: slope, intercept and the rms of the residuals") {
    const Line exact = leastSquaresLine({0.0, 1.0, 2.0, 3.0}, {1.0, 3.0, 5.0, 7.0});
    CHECK(exact.slope == doctest::Approx(2.0));
    CHECK(exact.intercept == doctest::Approx(1.0));
    CHECK(exact.rmsResidual == doctest::Approx(0.0));
    // A staircase: the line 0.3 + 0.8 x leaves residuals 0.2, -0.6, 0.6, -0.2.
    const Line stairs = leastSquaresLine({0.0, 1.0, 2.0, 3.0}, {0.5, 0.5, 2.5, 2.5});
    CHECK(stairs.slope == doctest::Approx(0.8));
    CHECK(stairs.intercept == doctest::Approx(0.3));
    CHECK(stairs.rmsResidual == doctest::Approx(std::sqrt(0.2)));

    CHECK_THROWS_AS(leastSquaresLine({0.0}, {1.0}), Error);
    CHECK_THROWS_AS(leastSquaresLine({1.0, 1.0}, {1.0, 2.0}), Error);  // no spread in x
    CHECK_THROWS_AS(leastSquaresLine({0.0, 1.0}, {1.0, NAN}), Error);
}

TEST_CASE("equation of state: the reference table and the closed forms") {
    for (const ReferenceZ& row : referenceTable()) CHECK(referenceZ(row.packing) == doctest::Approx(row.z));
    CHECK(referenceZ(0.5) == doctest::Approx(4.106));
    CHECK(referenceZ(0.1) == doctest::Approx(1.23614));

    CHECK(hendersonZ(0.5) == doctest::Approx(4.125));
    CHECK(hendersonZ(0.0) == 1.0);
    CHECK(ludingZ(0.0) == 1.0);
    CHECK(santosZ(0.0) == 1.0);
    // The second virial coefficient of hard disks: Z = 1 + 2 eta + O(eta^2) for every form.
    for (double (*z)(double) : {hendersonZ, ludingZ, santosZ})
        CHECK((z(1e-6) - 1.0) / 1e-6 == doctest::Approx(2.0).epsilon(1e-4));
    // Luding's form is what the table takes at 0.5 and 0.6 (within its spread).
    CHECK(ludingZ(0.6) == doctest::Approx(6.452).epsilon(0.001));
    CHECK(std::abs(ludingZ(0.5) - 4.106) < 0.005);

    // Between table points: between its neighbours, and close to Luding.
    const double between = referenceZ(0.45);
    CHECK(between > referenceZ(0.4));
    CHECK(between < referenceZ(0.5));
    CHECK(between == doctest::Approx(ludingZ(0.45)).epsilon(0.002));
    // Outside the table: Luding.
    CHECK(referenceZ(0.62) == ludingZ(0.62));
}

TEST_CASE("statisticalTolerance: the target, or three standard errors where they exceed it") {
    CHECK(statisticalTolerance(0.003, 0.0005) == 0.003);
    CHECK(statisticalTolerance(0.003, 0.002) == doctest::Approx(0.006));
    CHECK(statisticalTolerance(0.0, 0.01) == doctest::Approx(0.03));
}

TEST_CASE("collisionFrequency: 4 (Z - 1) / sigma sqrt(kT / pi m) from the mean normal speed of colliding pairs") {
    // At the reference's Z(0.5) = 4.106, disks of diameter 2 and mass 1 at
    // kT = 1 collide 3.5046 times per unit time each.
    CHECK(collisionFrequency(4.106, 1.0, 2.0, 1.0) == doctest::Approx(4.0 * 3.106 / 2.0 / std::sqrt(kPi)));
    CHECK(collisionFrequency(1.0, 1.0, 2.0, 1.0) == 0.0);  // no excess pressure, no collisions
    // Faster disks (kT / m four times larger) collide twice as often; twice larger ones half as often.
    CHECK(collisionFrequency(3.0, 4.0, 2.0, 1.0) == doctest::Approx(2.0 * collisionFrequency(3.0, 1.0, 2.0, 1.0)));
    CHECK(collisionFrequency(3.0, 2.0, 2.0, 0.5) == doctest::Approx(2.0 * collisionFrequency(3.0, 1.0, 2.0, 1.0)));
    CHECK(collisionFrequency(3.0, 1.0, 4.0, 1.0) == doctest::Approx(0.5 * collisionFrequency(3.0, 1.0, 2.0, 1.0)));

    // The formula's premise, checked by sampling: pairs of Maxwellian disks
    // (kT/m = 1.3) meet at a rate proportional to their normal approach speed
    // u_n = -(v_i - v_j).n > 0, so the colliding pairs' mean u_n is
    // <u_n^2> / <u_n> over approaching pairs, which must be sqrt(pi kT / m).
    const double kTOverMass = 1.3;
    std::mt19937_64 random(11);
    std::normal_distribution<double> component(0.0, std::sqrt(kTOverMass));
    double sum = 0.0, sumSquares = 0.0;
    for (int i = 0; i < 400000; ++i) {
        const double un = component(random) - component(random);  // along a fixed normal
        if (un > 0) {
            sum += un;
            sumSquares += un * un;
        }
    }
    CHECK(sumSquares / sum == doctest::Approx(std::sqrt(kPi * kTOverMass)).epsilon(0.005));
}
