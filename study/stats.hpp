#pragma once
// Statistics and output helpers of the study: log-log slope fits with t confidence intervals,
// and a minimal CSV table writer.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace oas::study {

/// Two-sided 95% Student-t quantile t_{0.975, df} (table for df <= 30, then interpolated in
/// 1/df through 40, 60, 120 and infinity; 3 decimals, as printed tables give it).
double tQuantile975(int df);

struct SlopeFit {
    double slope = 0, intercept = 0;
    double stderr_ = 0;            ///< standard error of the slope
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
    bool found = false;    ///< false: the curve never reaches target within the measured range
    bool atFirst = false;  ///< y.front() <= target already: x = x.front() is an upper bound
};
Crossing firstCrossing(const std::vector<double>& x, const std::vector<double>& y, double target);

/// A well-mixed 32-bit seed from up to four small integers (distinct trials, samplers, counts get
/// unrelated randomizations).
std::uint32_t mixSeed(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d = 0);

/// A mean over n independent draws with its standard error s.e. = sd / sqrt(n), sd the sample
/// standard deviation with n − 1 in the denominator (the usual unbiased variance; e.g. Rice,
/// "Mathematical Statistics and Data Analysis", §7.3). The study reports every relMSE as one.
struct Estimate {
    double mean = 0, se = 0;
    std::uint32_t n = 0;
    bool capped = false;  ///< the adaptive loop stopped at its cap before s.e. <= target × |mean|
    /// s.e. ÷ |mean| (infinite for a zero mean, NaN without data).
    double relSe() const;
};

/// Mean and standard error of the values (n = 1: s.e. NaN, unknown; empty: mean and s.e. NaN).
Estimate estimateOf(const std::vector<double>& values);

/// The verdict between two estimates of an error (lower is better): a difference counts only where
/// |a − b| > 2 sqrt(se_a² + se_b²), i.e. about a two-sided 95% test of equal means for independent
/// estimates (normal approximation); anything closer, or with an unknown s.e., is a tie.
enum class Verdict { Tie, FirstLower, SecondLower };
Verdict compare(const Estimate& a, const Estimate& b);
/// (a − b) / sqrt(se_a² + se_b²): how many combined standard errors a lies above b (NaN where
/// either s.e. is unknown).
double excessInStandardErrors(const Estimate& a, const Estimate& b);
/// The one-sided normal bound z with P(Z > z) = alpha / comparisons: a difference beyond it in
/// any of `comparisons` tests happens by chance with probability at most alpha when every pair is
/// equal (Bonferroni's inequality). One comparison at alpha 0.05: 1.645.
double familyWiseOneSidedBound(int comparisons, double alpha = 0.05);
/// "a < b", "a > b" as text for tables: "lower", "higher", "tie".
std::string verdictWord(Verdict v);

/// a / b with the first-order (delta-method) standard error r sqrt((se_a/a)² + (se_b/b)²), for
/// independent a and b; n is the smaller of the two, capped if either is.
Estimate ratioOf(const Estimate& a, const Estimate& b);
/// a + b for independent a and b (a stratified sum): s.e. sqrt(se_a² + se_b²); n is a's (the
/// estimate the sum is counted by: in the rare-pixel split, the image renders), not capped.
Estimate sumOf(const Estimate& a, const Estimate& b);

/// Adaptive number of independent draws per point: draw(i) returns draw i (i = 0, 1, ...; the
/// caller gives each its own seed). Takes nMin draws, then one more at a time while
/// s.e. > relTarget × |mean| and n < nMax; `capped` says the cap stopped it. Stopping on the s.e.
/// itself biases the s.e. low a little (the loop stops on a lucky stretch), which nMin limits.
struct AdaptiveOptions {
    double relTarget = 0.1;
    std::uint32_t nMin = 8, nMax = 64;
};
struct AdaptiveResult {
    Estimate estimate;
    std::vector<double> values;  ///< every draw, in order
};
AdaptiveResult adaptiveMean(const std::function<double(std::uint32_t)>& draw, const AdaptiveOptions& options);
/// The same for draws of several quantities at once (e.g. a render's full-image and crop relMSE):
/// keeps drawing while any of the first `targeted` quantities misses the target (the others are
/// carried along, e.g. the worst pixels' share); returns one result per quantity, all with the
/// same n. Every draw must return the same number of values (>= targeted).
std::vector<AdaptiveResult> adaptiveMeans(const std::function<std::vector<double>(std::uint32_t)>& draw, std::size_t targeted,
                                          const AdaptiveOptions& options);

/// One draw of a budgeted point: its values and what it cost (e.g. render seconds).
struct CostedDraw {
    std::vector<double> values;
    double cost = 0;
};
/// Adaptive draws for many points that share one budget (the scene study: every (sampler, spp) of
/// a scene shares its render time). Every point first takes nMin draws (not counted against the
/// budget). Then, while the extra cost spent is below `budget`, the next draw goes to the point
/// that it helps most per unit cost: among points with n < nMax whose worst targeted quantity has
/// s.e. > relTarget × |mean|, the one with the largest relSe / (n × mean cost per draw) (one more
/// draw shrinks a relative s.e. by about relSe / 2n). Points that meet the target get no more.
/// Returns, per point, one result per quantity; `capped` marks every quantity still above target.
/// draw(point, i) is called with i = 0, 1, ... in order for each point.
/// `keptDraws` (empty, or one count per point) continues an earlier run: point k first takes
/// max(nMin, keptDraws[k]) draws, none counted against the budget (the caller returns the earlier
/// run's values for i < keptDraws[k]), so that the budget buys only new draws.
std::vector<std::vector<AdaptiveResult>> budgetedMeans(std::size_t points,
                                                       const std::function<CostedDraw(std::size_t point, std::uint32_t i)>& draw,
                                                       std::size_t targeted, const AdaptiveOptions& options, double budget,
                                                       const std::vector<std::uint32_t>& keptDraws = {});

/// Piecewise log-log interpolation (as interpLogLog) of estimates: the mean is interpLogLog's, the
/// s.e. by the delta method on log y = (1 − u) log y_i + u log y_{i+1} for independent points:
/// se(log y) = sqrt(((1 − u) se_i/y_i)² + (u se_{i+1}/y_{i+1})²), se = y se(log y); n the smaller of
/// the two neighbours'. Capped where a neighbour it draws on is capped and its own s.e. is still
/// above relSeTarget × mean (a value read between a capped point and a converged one can have
/// the smaller s.e.: marking it "cap" beside an s.e. under the target would contradict the rule).
/// Timing noise in x is not included.
Estimate interpEstimate(const std::vector<double>& x, const std::vector<Estimate>& y, double at, double relSeTarget = 0.1);

/// Where a curve of estimates first comes down to a target estimate (firstCrossing on the means),
/// with a delta-method s.e. of the crossing time: on the crossed segment log y = a + b log x, so
/// se(log x) = sqrt(se(log y)² + (se_target/target)²) / |b|, se(log y) interpolated as in
/// interpEstimate; se = x se(log x). NaN s.e. when the crossing is at the first point (a bound) or
/// not found. Capped where a neighbour it draws on is capped, whatever its own s.e.: unlike
/// interpEstimate's, this s.e. divides by the segment's fitted slope, which a noisy capped point
/// makes unreliable (it can come out at 1% on a firefly-ridden curve), so the mark stays.
struct CrossingEstimate {
    Crossing crossing;
    Estimate x;  ///< mean = crossing.x
};
CrossingEstimate firstCrossing(const std::vector<double>& x, const std::vector<Estimate>& y, const Estimate& target);

/// "1.23e-03 ± 8.1e-05 (n=16)", with " cap, s.e. 14%" inside the brackets when the cap was hit
/// before the s.e. target; "—" for a non-finite mean.
std::string fmtEstimate(const Estimate& e, int digits = 3);
/// A ratio with its s.e.: "0.52 ± 0.04"; "—" when not finite.
std::string fmtRatio(const Estimate& r, int decimals = 2);

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

/// A CSV file read back (RFC 4180 quoting, as CsvTable writes it): the header and the rows, each a
/// map from column name to cell.
struct CsvRows {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    /// Column index of `name`; throws std::runtime_error naming `file` and the column if absent.
    size_t column(const std::string& name, const std::string& file) const;
};
/// Parses CSV text; a row whose width differs from the header's, or an unterminated quote, throws
/// std::runtime_error naming `file` and the line.
CsvRows parseCsv(const std::string& text, const std::string& file);
/// parseCsv of a file; throws std::runtime_error if it cannot be read.
CsvRows readCsv(const std::string& path);

/// Cell `name` of data row `rowIndex` of `t` (read from `file`) as a number: the whole cell must
/// parse (strtod), else std::runtime_error names the file, the row and the column.
double csvNumber(const CsvRows& t, const std::vector<std::string>& row, const std::string& name, const std::string& file,
                 size_t rowIndex);
/// csvNumber, which must be a whole number in [0, 2^32 - 1].
std::uint32_t csvCount(const CsvRows& t, const std::vector<std::string>& row, const std::string& name, const std::string& file,
                       size_t rowIndex);

/// "%.*g" formatting (round-trippable with digits = 17).
std::string fmtG(double v, int digits = 6);
/// Fixed decimals.
std::string fmtF(double v, int decimals = 2);

}  // namespace oas::study
