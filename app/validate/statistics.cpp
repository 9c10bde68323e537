#include "app/validate/statistics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <carom/types.h>

namespace carom::validation {

MeanAndError blockAverage(const std::vector<double>& blockMeans) {
    MeanAndError result;
    const double n = double(blockMeans.size());
    if (blockMeans.empty()) return result;
    for (double m : blockMeans) result.mean += m;
    result.mean /= n;
    if (blockMeans.size() < 2) return result;
    double squares = 0.0;
    for (double m : blockMeans) squares += (m - result.mean) * (m - result.mean);
    result.error = std::sqrt(squares / (n - 1.0) / n);
    return result;
}

MeanAndError blockingAverage(std::vector<double> blockMeans, std::size_t minBlocks) {
    MeanAndError result = blockAverage(blockMeans);
    while (blockMeans.size() / 2 >= std::max<std::size_t>(minBlocks, 2)) {
        std::vector<double> merged;
        for (std::size_t i = 0; i + 1 < blockMeans.size(); i += 2)
            merged.push_back(0.5 * (blockMeans[i] + blockMeans[i + 1]));
        blockMeans = std::move(merged);
        result.error = std::max(result.error, blockAverage(blockMeans).error);
    }
    return result;
}

double statisticalTolerance(double target, double error) { return std::max(target, 3.0 * error); }

double rayleighCdf(double speed, double kTOverMass) { return -std::expm1(-speed * speed / (2.0 * kTOverMass)); }

double rayleighPdf(double speed, double kTOverMass) {
    return speed / kTOverMass * std::exp(-speed * speed / (2.0 * kTOverMass));
}

double ksRayleigh(std::vector<double> speeds, double kTOverMass) {
    std::sort(speeds.begin(), speeds.end());
    const double n = double(speeds.size());
    double statistic = 0.0;
    // The empirical CDF jumps from i/n to (i+1)/n at the i-th smallest speed.
    for (std::size_t i = 0; i < speeds.size(); ++i) {
        const double cdf = rayleighCdf(speeds[i], kTOverMass);
        statistic = std::max({statistic, cdf - double(i) / n, double(i + 1) / n - cdf});
    }
    return statistic;
}

double ksCritical05(std::size_t n) { return n > 0 ? 1.358 / std::sqrt(double(n)) : 0.0; }

double HEstimate::bias() const {
    return samples > 0 && occupiedBins > 0 ? double(occupiedBins - 1) / (2.0 * double(samples)) : 0.0;
}

HEstimate hFunction(const std::vector<double>& vx, const std::vector<double>& vy, const VelocityHistogram& histogram) {
    const int bins = histogram.binsPerAxis;
    const double binWidth = 2.0 * histogram.range / bins;
    std::vector<std::size_t> counts(std::size_t(bins) * std::size_t(bins), 0);
    HEstimate estimate;
    estimate.samples = std::min(vx.size(), vy.size());
    for (std::size_t i = 0; i < estimate.samples; ++i) {
        const double bx = std::floor((vx[i] + histogram.range) / binWidth);
        const double by = std::floor((vy[i] + histogram.range) / binWidth);
        if (!(bx >= 0 && bx < bins && by >= 0 && by < bins)) {
            ++estimate.outside;
            continue;
        }
        ++counts[std::size_t(by) * std::size_t(bins) + std::size_t(bx)];
    }
    const double n = double(estimate.samples);
    const double binArea = binWidth * binWidth;
    for (std::size_t count : counts) {
        if (count == 0) continue;
        ++estimate.occupiedBins;
        const double probability = double(count) / n;
        // f = p / area over the bin, so the bin's share of the integral is p ln(p / area).
        estimate.value += probability * std::log(probability / binArea);
    }
    return estimate;
}

double hEquilibrium(double kTOverMass) { return std::log(1.0 / (2.0 * kPi * kTOverMass)) - 1.0; }

Line leastSquaresLine(const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size() || x.size() < 2)
        throw Error("leastSquaresLine needs at least two (x, y) pairs of equal count");
    double sx = 0, sy = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!(std::isfinite(x[i]) && std::isfinite(y[i]))) {
            std::ostringstream message;
            message << "leastSquaresLine needs finite values, got (" << x[i] << ", " << y[i] << ")";
            throw Error(message.str());
        }
        sx += x[i];
        sy += y[i];
    }
    const double n = double(x.size());
    const double meanX = sx / n, meanY = sy / n;
    double sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxx += (x[i] - meanX) * (x[i] - meanX);
        sxy += (x[i] - meanX) * (y[i] - meanY);
    }
    if (!(sxx > 0)) throw Error("leastSquaresLine needs at least two distinct x values");
    Line line;
    line.slope = sxy / sxx;
    line.intercept = meanY - line.slope * meanX;
    double squares = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double residual = y[i] - (line.intercept + line.slope * x[i]);
        squares += residual * residual;
    }
    line.rmsResidual = std::sqrt(squares / n);
    return line;
}

double hendersonZ(double eta) { return (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta)); }

double ludingZ(double eta) {
    const double free = 1.0 - eta;
    const double contactValue =
        (1.0 - 7.0 * eta / 16.0) / (free * free) - eta * eta * eta / (128.0 * std::pow(free, 4));
    return 1.0 + 2.0 * eta * contactValue;
}

double santosZ(double eta) {
    const double closePacked = kPi / (2.0 * std::sqrt(3.0));
    return 1.0 / (1.0 - 2.0 * eta + (2.0 * closePacked - 1.0) * eta * eta / (closePacked * closePacked));
}

double collisionFrequency(double z, double kT, double diameter, double mass) {
    return 4.0 * (z - 1.0) / diameter * std::sqrt(kT / (kPi * mass));
}

const std::vector<ReferenceZ>& referenceTable() {
    static const std::vector<ReferenceZ> table = {{0.1, 1.23614, 0.0},  {0.2, 1.57037, 0.0}, {0.3, 2.0633, 0.0},
                                                  {0.4, 2.8293, 0.001}, {0.5, 4.106, 0.003}, {0.6, 6.452, 0.005}};
    return table;
}

double referenceZ(double eta) {
    const std::vector<ReferenceZ>& table = referenceTable();
    if (!(eta >= table.front().packing && eta <= table.back().packing)) return ludingZ(eta);
    for (std::size_t k = 0; k + 1 < table.size(); ++k) {
        const ReferenceZ& lo = table[k];
        const ReferenceZ& hi = table[k + 1];
        if (eta > hi.packing) continue;
        const double f = (eta - lo.packing) / (hi.packing - lo.packing);
        const double ratio = (1.0 - f) * lo.z / ludingZ(lo.packing) + f * hi.z / ludingZ(hi.packing);
        return ratio * ludingZ(eta);
    }
    return table.back().z;
}

}  // namespace carom::validation
