#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace oas::study {

double tQuantile975(int df)
{
    static const double table[31] = {0,     12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                                     2.201, 2.179,  2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080,
                                     2.074, 2.069,  2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042};
    if (df < 1) return std::nan("");
    if (df <= 30) return table[df];
    // Interpolate linearly in 1/df between tabulated points.
    static const double dfs[] = {30, 40, 60, 120, 1e300};
    static const double ts[] = {2.042, 2.021, 2.000, 1.980, 1.960};
    for (int i = 0; i < 4; ++i) {
        if (df <= dfs[i + 1]) {
            const double a = 1 / dfs[i], b = 1 / dfs[i + 1], u = (a - 1.0 / df) / (a - b);
            return ts[i] + u * (ts[i + 1] - ts[i]);
        }
    }
    return 1.960;
}

SlopeFit fitLine(const std::vector<double>& x, const std::vector<double>& y)
{
    SlopeFit fit;
    const size_t n = std::min(x.size(), y.size());
    fit.n = int(n);
    if (n < 2) return fit;
    double mx = 0, my = 0;
    for (size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
    mx /= n, my /= n;
    double sxx = 0, sxy = 0, syy = 0;
    for (size_t i = 0; i < n; ++i) {
        sxx += (x[i] - mx) * (x[i] - mx);
        sxy += (x[i] - mx) * (y[i] - my);
        syy += (y[i] - my) * (y[i] - my);
    }
    fit.slope = sxy / sxx;
    fit.intercept = my - fit.slope * mx;
    double sse = 0;
    for (size_t i = 0; i < n; ++i) {
        const double r = y[i] - fit.intercept - fit.slope * x[i];
        sse += r * r;
    }
    fit.r2 = syy > 0 ? 1 - sse / syy : 1;
    if (n >= 3) {
        fit.stderr_ = std::sqrt(sse / (n - 2) / sxx);
        const double t = tQuantile975(int(n) - 2);
        fit.ciLow = fit.slope - t * fit.stderr_;
        fit.ciHigh = fit.slope + t * fit.stderr_;
    } else {
        fit.stderr_ = fit.ciLow = fit.ciHigh = std::nan("");
    }
    return fit;
}

SlopeFit fitLogLog(const std::vector<double>& x, const std::vector<double>& y)
{
    std::vector<double> lx, ly;
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
        if (!(x[i] > 0) || !(y[i] > 0) || !std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
        lx.push_back(std::log(x[i]));
        ly.push_back(std::log(y[i]));
    }
    return fitLine(lx, ly);
}

void CsvTable::add(std::vector<std::string> row)
{
    if (row.size() != header_.size())
        throw std::invalid_argument("CsvTable: row has " + std::to_string(row.size()) + " cells, header " +
                                    std::to_string(header_.size()));
    rows_.push_back(std::move(row));
}

namespace {
std::string quote(const std::string& cell)
{
    if (cell.find_first_of(",\"\n\r") == std::string::npos) return cell;
    std::string out = "\"";
    for (char c : cell) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}
void appendRow(std::string& out, const std::vector<std::string>& row)
{
    for (size_t i = 0; i < row.size(); ++i) {
        if (i) out += ',';
        out += quote(row[i]);
    }
    out += '\n';
}
}  // namespace

std::string CsvTable::str() const
{
    std::string out;
    appendRow(out, header_);
    for (auto& r : rows_) appendRow(out, r);
    return out;
}

void CsvTable::write(const std::string& path) const
{
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary);
        if (!f) throw std::runtime_error("cannot write " + tmp);
        f << str();
        if (!f) throw std::runtime_error("write failed: " + tmp);
    }
    std::filesystem::rename(tmp, path);
}

size_t CsvRows::column(const std::string& name, const std::string& file) const
{
    for (size_t i = 0; i < header.size(); ++i)
        if (header[i] == name) return i;
    throw std::runtime_error(file + ": no column \"" + name + "\"");
}

CsvRows parseCsv(const std::string& text, const std::string& file)
{
    CsvRows out;
    std::vector<std::string> row;
    std::string cell;
    bool quoted = false, any = false;
    size_t line = 1, rowLine = 1;
    auto endRow = [&] {
        row.push_back(cell);
        cell.clear();
        const bool blank = row.size() == 1 && row[0].empty() && !any;  // an empty line
        if (!blank && out.header.empty()) {
            out.header = row;
        } else if (!blank) {
            if (row.size() != out.header.size())
                throw std::runtime_error(file + ":" + std::to_string(rowLine) + ": " + std::to_string(row.size()) +
                                         " cells, the header has " + std::to_string(out.header.size()));
            out.rows.push_back(row);
        }
        row.clear();
        any = false;
        rowLine = line;
    };
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"')
                cell += '"', ++i;
            else if (c == '"')
                quoted = false;
            else {
                if (c == '\n') ++line;
                cell += c;
            }
        } else if (c == '"')
            quoted = any = true;
        else if (c == ',')
            row.push_back(cell), cell.clear(), any = true;
        else if (c == '\r')
            continue;
        else if (c == '\n')
            ++line, endRow();
        else
            cell += c, any = true;
    }
    if (quoted) throw std::runtime_error(file + ":" + std::to_string(rowLine) + ": unterminated quoted cell");
    if (any || !cell.empty() || !row.empty()) endRow();
    return out;
}

CsvRows readCsv(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cannot read " + path);
    std::ostringstream text;
    text << f.rdbuf();
    return parseCsv(text.str(), path);
}

std::string fmtG(double v, int digits)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

std::string fmtF(double v, int decimals)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

}  // namespace oas::study

namespace oas::study {

double interpLogLog(const std::vector<double>& x, const std::vector<double>& y, double at)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (x.size() != y.size() || x.empty() || !(at > 0)) return nan;
    if (at < x.front() * (1 - 1e-12) || at > x.back() * (1 + 1e-12)) return nan;
    for (size_t i = 0; i + 1 < x.size(); ++i) {
        if (at > x[i + 1]) continue;
        if (!(x[i] > 0 && x[i + 1] > x[i] && y[i] > 0 && y[i + 1] > 0)) return nan;
        const double u = std::log(at / x[i]) / std::log(x[i + 1] / x[i]);
        return std::exp(std::log(y[i]) + std::clamp(u, 0.0, 1.0) * std::log(y[i + 1] / y[i]));
    }
    return y.back() > 0 ? y.back() : nan;  // single point, at == x
}

Crossing firstCrossing(const std::vector<double>& x, const std::vector<double>& y, double target)
{
    Crossing c;
    if (x.size() != y.size() || x.empty() || !(target > 0)) return c;
    if (y.front() <= target) {
        c.x = x.front();
        c.found = c.atFirst = true;
        return c;
    }
    for (size_t i = 0; i + 1 < x.size(); ++i) {
        if (!(y[i] > target && y[i + 1] <= target)) continue;
        if (!(x[i] > 0 && x[i + 1] > 0 && y[i + 1] > 0)) return c;
        const double u = std::log(target / y[i]) / std::log(y[i + 1] / y[i]);
        c.x = std::exp(std::log(x[i]) + u * std::log(x[i + 1] / x[i]));
        c.found = true;
        return c;
    }
    return c;
}

std::uint32_t mixSeed(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d)
{
    std::uint32_t h = 0x9E3779B9u * (a + 1) ^ (b * 0x85EBCA6Bu) ^ (c * 0xC2B2AE35u) ^ (d * 0x27D4EB2Fu);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    return h;
}

double median(std::vector<double> v)
{
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace oas::study

namespace oas::study {

double Estimate::relSe() const
{
    if (n == 0 || !std::isfinite(mean)) return std::numeric_limits<double>::quiet_NaN();
    return mean == 0 ? std::numeric_limits<double>::infinity() : se / std::abs(mean);
}

Estimate estimateOf(const std::vector<double>& values)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Estimate e;
    e.n = std::uint32_t(values.size());
    if (values.empty()) {
        e.mean = e.se = nan;
        return e;
    }
    double m = 0;
    for (double v : values) m += v;
    m /= double(values.size());
    e.mean = m;
    if (values.size() < 2) {
        e.se = nan;
        return e;
    }
    // Two-pass sum of squared deviations (numerically stable for the tiny, similar relMSEs here).
    double ss = 0;
    for (double v : values) ss += (v - m) * (v - m);
    e.se = std::sqrt(ss / double(values.size() - 1) / double(values.size()));
    return e;
}

Verdict compare(const Estimate& a, const Estimate& b)
{
    const double d = a.mean - b.mean, band = 2 * std::sqrt(a.se * a.se + b.se * b.se);
    if (!std::isfinite(d) || !std::isfinite(band)) return Verdict::Tie;
    if (std::abs(d) <= band) return Verdict::Tie;
    return d < 0 ? Verdict::FirstLower : Verdict::SecondLower;
}

double excessInStandardErrors(const Estimate& a, const Estimate& b)
{
    const double band = std::sqrt(a.se * a.se + b.se * b.se);
    return band > 0 ? (a.mean - b.mean) / band : std::nan("");
}

double familyWiseOneSidedBound(int comparisons, double alpha)
{
    if (comparisons < 1 || !(alpha > 0 && alpha < 1))
        throw std::invalid_argument("familyWiseOneSidedBound: comparisons >= 1 and 0 < alpha < 1 (got " +
                                    std::to_string(comparisons) + ", " + std::to_string(alpha) + ")");
    // P(Z > z) = erfc(z / sqrt 2) / 2 falls with z: bisect on [-40, 40] to double precision.
    const double tail = alpha / comparisons;
    double lo = -40, hi = 40;
    for (int i = 0; i < 200 && hi - lo > 1e-12; ++i) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(mid / std::sqrt(2.0)) > tail ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

std::string verdictWord(Verdict v)
{
    switch (v) {
    case Verdict::FirstLower:
        return "lower";
    case Verdict::SecondLower:
        return "higher";
    default:
        return "tie";
    }
}

Estimate ratioOf(const Estimate& a, const Estimate& b)
{
    Estimate r;
    r.mean = a.mean / b.mean;
    const double ra = a.se / a.mean, rb = b.se / b.mean;
    r.se = std::abs(r.mean) * std::sqrt(ra * ra + rb * rb);
    r.n = std::min(a.n, b.n);
    r.capped = a.capped || b.capped;
    return r;
}

Estimate sumOf(const Estimate& a, const Estimate& b)
{
    Estimate r;
    r.mean = a.mean + b.mean;
    r.se = std::sqrt(a.se * a.se + b.se * b.se);
    r.n = a.n;
    return r;
}

namespace {

/// The draws of one point and the tests on them (budgetedMeans; adaptiveMeans is its one-point case).
struct DrawnPoint {
    std::vector<AdaptiveResult> r;
    std::uint32_t n = 0;
    double cost = 0;
    void add(const std::vector<double>& v, std::size_t targeted)
    {
        if (r.empty()) r.resize(v.size());
        if (v.size() != r.size() || v.size() < targeted)
            throw std::invalid_argument("adaptive draws: a draw returned " + std::to_string(v.size()) + " values");
        for (size_t k = 0; k < v.size(); ++k) r[k].values.push_back(v[k]);
        ++n;
    }
    /// The largest relative s.e. of the targeted quantities; relSe() is NaN for n = 1 and infinite
    /// for a zero mean: both count as "far from the target" (a large finite number).
    double worstRelSe(std::size_t targeted) const
    {
        double w = 0;
        for (size_t k = 0; k < targeted; ++k) {
            const double e = estimateOf(r[k].values).relSe();
            w = std::max(w, std::isfinite(e) ? e : 1e9);
        }
        return w;
    }
    void finish(double relTarget)
    {
        for (auto& q : r) {
            q.estimate = estimateOf(q.values);
            // Marked per quantity: the cap stopped the draws before its s.e. met the target.
            q.estimate.capped = !(q.estimate.relSe() <= relTarget);
        }
    }
};

}  // namespace

std::vector<std::vector<AdaptiveResult>> budgetedMeans(std::size_t points,
                                                       const std::function<CostedDraw(std::size_t point, std::uint32_t i)>& draw,
                                                       std::size_t targeted, const AdaptiveOptions& o, double budget,
                                                       const std::vector<std::uint32_t>& keptDraws)
{
    const std::uint32_t nMax = std::max<std::uint32_t>(1, o.nMax), nMin = std::clamp<std::uint32_t>(o.nMin, 1, nMax);
    if (!keptDraws.empty() && keptDraws.size() != points)
        throw std::invalid_argument("budgetedMeans: " + std::to_string(keptDraws.size()) + " kept-draw counts for " +
                                    std::to_string(points) + " points");
    std::vector<DrawnPoint> ps(points);
    auto drawOne = [&](std::size_t k) {
        const CostedDraw d = draw(k, ps[k].n);
        ps[k].add(d.values, targeted);
        ps[k].cost += d.cost;
        return d.cost;
    };
    for (std::size_t k = 0; k < points; ++k)
        while (ps[k].n < std::max(nMin, keptDraws.empty() ? 0u : keptDraws[k])) drawOne(k);
    double spent = 0;
    while (spent < budget) {
        std::size_t best = points;
        double bestPriority = -1;
        for (std::size_t k = 0; k < points; ++k) {
            if (ps[k].n >= nMax) continue;
            const double e = ps[k].worstRelSe(targeted);
            if (e <= o.relTarget) continue;
            const double perDraw = std::max(ps[k].cost / ps[k].n, 1e-12);
            const double priority = e / (ps[k].n * perDraw);
            if (priority > bestPriority) bestPriority = priority, best = k;
        }
        if (best == points) break;  // every point met its target or its cap
        spent += std::max(0.0, drawOne(best));
    }
    std::vector<std::vector<AdaptiveResult>> out;
    for (auto& p : ps) {
        p.finish(o.relTarget);
        out.push_back(std::move(p.r));
    }
    return out;
}

// One point with an unlimited budget is exactly the per-point loop: nMin draws, then more while
// above the target and below nMax.
std::vector<AdaptiveResult> adaptiveMeans(const std::function<std::vector<double>(std::uint32_t)>& draw, std::size_t targeted,
                                          const AdaptiveOptions& o)
{
    return budgetedMeans(
               1,
               [&](std::size_t, std::uint32_t i) {
                   return CostedDraw{draw(i), 1.0};
               },
               targeted, o, std::numeric_limits<double>::infinity())
        .front();
}

AdaptiveResult adaptiveMean(const std::function<double(std::uint32_t)>& draw, const AdaptiveOptions& o)
{
    return adaptiveMeans([&](std::uint32_t i) { return std::vector<double>{draw(i)}; }, 1, o).front();
}

CrossingEstimate firstCrossing(const std::vector<double>& x, const std::vector<Estimate>& y, const Estimate& target)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CrossingEstimate c;
    std::vector<double> means;
    for (const auto& v : y) means.push_back(v.mean);
    c.crossing = firstCrossing(x, means, target.mean);
    c.x.mean = c.crossing.found ? c.crossing.x : nan;
    c.x.se = nan;
    if (c.crossing.found && c.crossing.atFirst) c.x.n = y.front().n, c.x.capped = y.front().capped;
    if (!c.crossing.found || c.crossing.atFirst) return c;
    size_t i = 0;  // the crossed segment, as firstCrossing finds it
    while (i + 1 < x.size() && !(means[i] > target.mean && means[i + 1] <= target.mean)) ++i;
    // Position u of the crossing on the segment in log x, computed directly (not by interpEstimate:
    // measured times need not be ascending, e.g. Random's 121 and 128 spp renders).
    const double lx = std::log(x[i + 1] / x[i]);
    const double u = lx != 0 ? std::clamp(std::log(c.crossing.x / x[i]) / lx, 0.0, 1.0) : 0.0;
    const double ri = (1 - u) * y[i].se / y[i].mean, rj = u * y[i + 1].se / y[i + 1].mean;
    const double b = lx != 0 ? std::log(means[i + 1] / means[i]) / lx : nan;
    const double rt = target.se / target.mean;
    c.x.se = c.crossing.x * std::sqrt(ri * ri + rj * rj + rt * rt) / std::abs(b);
    c.x.n = u <= 0 ? y[i].n : u >= 1 ? y[i + 1].n : std::min(y[i].n, y[i + 1].n);
    c.x.capped = (u < 1 && y[i].capped) || (u > 0 && y[i + 1].capped);
    return c;
}

Estimate interpEstimate(const std::vector<double>& x, const std::vector<Estimate>& y, double at, double relSeTarget)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Estimate e;
    e.mean = e.se = nan;
    if (x.size() != y.size() || x.empty() || !(at > 0)) return e;
    std::vector<double> means;
    for (const auto& v : y) means.push_back(v.mean);
    e.mean = interpLogLog(x, means, at);
    if (!std::isfinite(e.mean)) return e;
    // The bracketing pair (the same search as interpLogLog).
    size_t i = 0;
    while (i + 1 < x.size() && at > x[i + 1]) ++i;
    const size_t j = std::min(i + 1, x.size() - 1);
    const double u = j == i ? 0.0 : std::clamp(std::log(at / x[i]) / std::log(x[j] / x[i]), 0.0, 1.0);
    const double ri = (1 - u) * y[i].se / y[i].mean, rj = u * y[j].se / y[j].mean;
    e.se = e.mean * std::sqrt(ri * ri + (u > 0 ? rj * rj : 0.0));
    e.n = u <= 0 ? y[i].n : u >= 1 ? y[j].n : std::min(y[i].n, y[j].n);
    e.capped = ((u < 1 && y[i].capped) || (u > 0 && y[j].capped)) && !(e.relSe() <= relSeTarget);
    return e;
}

std::string fmtEstimate(const Estimate& e, int digits)
{
    if (!std::isfinite(e.mean)) return "—";
    std::string s = fmtG(e.mean, digits);
    if (std::isfinite(e.se)) s += " ± " + fmtG(e.se, 2);
    s += " (n=" + std::to_string(e.n);
    if (e.capped) {
        const double rel = e.relSe();
        s += std::string(", cap; s.e. ") + (std::isfinite(rel) ? fmtF(100 * rel, 0) + "%" : "unknown");
    }
    return s + ")";
}

std::string fmtRatio(const Estimate& r, int decimals)
{
    if (!std::isfinite(r.mean)) return "—";
    return fmtF(r.mean, decimals) + (std::isfinite(r.se) ? " ± " + fmtF(r.se, decimals) : "");
}

/// Cell `name` of `row` as a number: the whole cell must parse (strtod), else the error names the
/// file, the data row and the column.
double csvNumber(const CsvRows& t, const std::vector<std::string>& row, const std::string& name, const std::string& file,
                 size_t rowIndex)
{
    const std::string& cell = row[t.column(name, file)];
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size())
        throw std::runtime_error(file + ": row " + std::to_string(rowIndex + 1) + ", column \"" + name + "\": \"" + cell +
                                 "\" is not a number");
    return v;
}

std::uint32_t csvCount(const CsvRows& t, const std::vector<std::string>& row, const std::string& name, const std::string& file,
                       size_t rowIndex)
{
    const double v = csvNumber(t, row, name, file, rowIndex);
    if (!(v >= 0 && v <= 4294967295.0) || v != std::floor(v))
        throw std::runtime_error(file + ": row " + std::to_string(rowIndex + 1) + ", column \"" + name + "\": " + fmtG(v) +
                                 " is not a count in [0, 2^32 - 1]");
    return std::uint32_t(v);
}

}  // namespace oas::study
