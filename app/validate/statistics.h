// The pure mathematics of `carom validate`: block averages, the
// Kolmogorov-Smirnov test against the 2D Maxwell-Boltzmann (Rayleigh) speed
// distribution, the Boltzmann H-function, observed orders of convergence and
// the hard-disk equation of state, with the formulas and the table of the
// hard-disk reference (shared/physics/hard-disks.md).
#pragma once

#include <cstddef>
#include <vector>

namespace carom::validation {

struct MeanAndError {
    double mean = 0.0;
    double error = 0.0;  // standard error of the mean
};

// The mean of block averages and its standard error, sqrt(var / n) with the
// n - 1 variance. Blocks long compared with the correlation time are
// independent, so this error is honest where the per-sample one is not.
// Error 0 for fewer than two blocks.
MeanAndError blockAverage(const std::vector<double>& blockMeans);

// The same mean with an error that allows for correlations between
// consecutive blocks (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461, 1989):
// the blocks are merged in adjacent pairs, level by level (an odd last one
// left out), while at least `minBlocks` remain, and the error is the largest
// of the levels' standard errors. Independent blocks give the same error at
// every level; correlated ones make it grow with the merged length until
// that outlasts the correlation. In 2D the pressure's time correlation has
// a slowly decaying (1/t) tail, so blocks of a few collision times are not
// independent.
MeanAndError blockingAverage(std::vector<double> blockMeans, std::size_t minBlocks);

// The tolerance of a comparison whose target is `target`: the target, or
// three standard errors where the run is too short to resolve it (a
// deviation within 3 errors is what chance gives 0.3 % of the time).
double statisticalTolerance(double target, double error);

// The Rayleigh distribution of speeds in 2D at kT/m = `kTOverMass`:
// F(v) = 1 - exp(-v^2 / (2 kT/m)), f(v) = v / (kT/m) exp(-v^2 / (2 kT/m)).
double rayleighCdf(double speed, double kTOverMass);
double rayleighPdf(double speed, double kTOverMass);

// The Kolmogorov-Smirnov statistic sup |F_n(v) - F(v)| of `speeds` against
// the Rayleigh CDF; 0 for no speeds.
double ksRayleigh(std::vector<double> speeds, double kTOverMass);

// The KS critical statistic at significance 0.05 for n samples, 1.358 / sqrt(n)
// (the asymptotic value, good for n above about 35).
double ksCritical05(std::size_t n);

// The square histogram of 2D velocities over [-range, range]^2 that
// hFunction estimates from.
struct VelocityHistogram {
    double range = 1.0;    // half-width of the square, > 0
    int binsPerAxis = 10;  // >= 1
};

struct HEstimate {
    // H = integral of f ln f d^2v, from the histogram density (the plug-in
    // estimate): biased high by about (occupied bins - 1) / (2 n).
    double value = 0.0;
    std::size_t samples = 0;  // n
    std::size_t occupiedBins = 0;
    std::size_t outside = 0;  // samples outside the square: counted in n, in no bin
    double bias() const;      // (occupiedBins - 1) / (2 n), the expected bias of `value`
};

// The Boltzmann H-function of the velocities (vx[i], vy[i]), i < n.
HEstimate hFunction(const std::vector<double>& vx, const std::vector<double>& vy, const VelocityHistogram& histogram);

// H of the equilibrium (Gaussian) distribution, ln(m / (2 pi kT)) - 1.
double hEquilibrium(double kTOverMass);

// The straight line y = intercept + slope x fitted to (x, y) by least
// squares, and the root mean square of the residuals about it.
struct Line {
    double slope = 0.0;
    double intercept = 0.0;
    double rmsResidual = 0.0;
};

// Needs at least two points of equal count, all finite, and two distinct x;
// throws Error otherwise.
Line leastSquaresLine(const std::vector<double>& x, const std::vector<double>& y);

// The compressibility factor Z = PA / (N kT) of the hard-disk fluid at
// packing fraction eta, from the closed forms of the reference.
double hendersonZ(double packing);  // (1 + eta^2/8) / (1 - eta)^2
double ludingZ(double packing);     // 1 + 2 eta g(sigma)
double santosZ(double packing);     // 1 / (1 - 2 eta + (2 eta_cp - 1) eta^2 / eta_cp^2)

// The collision frequency of one disk (collisions it takes part in per unit
// time) in an equilibrium fluid of equal hard disks of diameter sigma and
// mass m in 2D: omega = 4 (Z - 1) / sigma * sqrt(kT / (pi m)). The collision
// virial gives Z - 1 = sigma <|v_n|> omega / (4 kT), and the normal relative
// speed of colliding pairs averages sqrt(pi kT / m) (a flux-weighted
// Maxwellian of variance 2 kT / m), whatever the density.
double collisionFrequency(double z, double kT, double diameter, double mass);

// One row of the reference table.
struct ReferenceZ {
    double packing = 0.0;
    double z = 0.0;
    double uncertainty = 0.0;  // as published; 0 where the table gives all digits
};

// The table of the reference, eta = 0.1 ... 0.6.
const std::vector<ReferenceZ>& referenceTable();

// The best Z at any packing: the table value at its points; between them
// Luding's form scaled by the linearly interpolated ratio table / Luding
// (the ratio is within 0.1 % of 1, so this is far smoother than
// interpolating Z); outside the table, Luding's form.
double referenceZ(double packing);

}  // namespace carom::validation
