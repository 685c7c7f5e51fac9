#pragma once
// Statistics and output helpers of the study: log-log slope fits with t confidence intervals,
// and a minimal CSV table writer.
#include <string>
#include <vector>

namespace oas::study {

/// Two-sided 95% Student-t quantile t_{0.975, df} (table for df <= 30, then interpolated in
/// 1/df through 40, 60, 120 and infinity; 3 decimals, as printed tables give it).
double tQuantile975(int df);

struct SlopeFit {
    double slope = 0, intercept = 0;
    double stderr_ = 0;       ///< standard error of the slope
    double ciLow = 0, ciHigh = 0;  ///< 95% confidence interval (t, n - 2 degrees of freedom)
    int n = 0;
    double r2 = 0;
    bool valid() const { return n >= 3; }
};

/// Least squares of log(y) on log(x); points with y <= 0 or non-finite are skipped.
SlopeFit fitLogLog(const std::vector<double>& x, const std::vector<double>& y);
/// Plain least squares of y on x.
SlopeFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

/// Piecewise-linear interpolation of log y over log x at `at` (x ascending, all positive);
/// NaN when `at` lies outside [x.front(), x.back()] or the inputs are unusable. The study reads
/// "error at equal time" off measured error-versus-time curves with it.
double interpLogLog(const std::vector<double>& x, const std::vector<double>& y, double at);

/// Where a measured curve first comes down to `target`: the x at which the piecewise log-log
/// line through (x, y) (x ascending) reaches y = target ("time to reach a target error").
struct Crossing {
    double x = 0;
    bool found = false;       ///< false: the curve never reaches target within the measured range
    bool atFirst = false;     ///< y.front() <= target already: x = x.front() is an upper bound
};
Crossing firstCrossing(const std::vector<double>& x, const std::vector<double>& y, double target);

/// A well-mixed 32-bit seed from up to four small integers (distinct trials, samplers, counts get
/// unrelated randomizations).
std::uint32_t mixSeed(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d = 0);

/// Median of the values (NaN when empty).
double median(std::vector<double> v);

/// A CSV table: a header and rows of already formatted cells; cells with commas, quotes or
/// newlines are quoted (RFC 4180).
class CsvTable {
public:
    explicit CsvTable(std::vector<std::string> header) : header_(std::move(header)) {}
    void add(std::vector<std::string> row);  ///< throws std::invalid_argument on a wrong width
    std::string str() const;
    void write(const std::string& path) const;  ///< atomically-ish: temp file, then rename
    size_t rows() const { return rows_.size(); }
    const std::vector<std::string>& header() const { return header_; }

private:
    std::vector<std::string> header_;
    std::vector<std::vector<std::string>> rows_;
};

/// "%.*g" formatting (round-trippable with digits = 17).
std::string fmtG(double v, int digits = 6);
/// Fixed decimals.
std::string fmtF(double v, int decimals = 2);

}  // namespace oas::study
