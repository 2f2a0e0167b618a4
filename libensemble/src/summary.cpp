#include "ecoterra/ensemble/summary.hpp"

#include "ecoterra/analyses/analyses.hpp"

#include "ecoterra/ensemble/member.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/io/hdf5_writer.hpp"
#include "ecoterra/run/pictures.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace ecoterra::ensemble {

namespace fs = std::filesystem;
using nlohmann::json;

std::string index_ranges(const std::vector<std::size_t>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size();) {
        std::size_t j = i;
        while (j + 1 < v.size() && v[j + 1] == v[j] + 1) ++j;
        if (!s.empty()) s += ",";
        s += std::to_string(v[i]);
        if (j > i) {
            s += "-";
            s += std::to_string(v[j]);
        }
        i = j + 1;
    }
    return s;
}

std::string unit_of(const std::string& c) {
    return analyses::column_unit(c);
}

namespace {

struct Stats {
    double mean = NAN, sd = NAN, p10 = NAN, p50 = NAN, p90 = NAN;
    std::size_t n = 0;
};

double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return NAN;
    const double h = q * static_cast<double>(sorted.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(h));
    const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

Stats stats(std::vector<double> v) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }),
            v.end());
    Stats s;
    s.n = v.size();
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / static_cast<double>(v.size());
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
    s.p10 = quantile(v, 0.1);
    s.p50 = quantile(v, 0.5);
    s.p90 = quantile(v, 0.9);
    return s;
}

/// The shortest text that reads back as the same double; empty for NaN.
std::string num(double v) {
    if (!std::isfinite(v)) return "";
    char b[40];
    const auto r = std::to_chars(b, b + sizeof b, v);
    return std::string(b, r.ptr);
}

std::string csv_cell(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

/// A table of named columns, each a number, an integer or text, written as CSV and into an
/// HDF5 group (integers as integers, so seeds stay exact).
struct Columns {
    enum Type { number, integer, text };
    std::vector<std::string> names;
    std::vector<Type> types;
    std::vector<std::vector<double>> numbers;
    std::vector<std::vector<std::int64_t>> integers;
    std::vector<std::vector<std::string>> strings;
    std::size_t add(const std::string& name, Type t) {
        names.push_back(name);
        types.push_back(t);
        numbers.emplace_back();
        integers.emplace_back();
        strings.emplace_back();
        return names.size() - 1;
    }
    std::size_t rows() const {
        if (names.empty()) return 0;
        return types[0] == text      ? strings[0].size()
               : types[0] == integer ? integers[0].size()
                                     : numbers[0].size();
    }
    std::string csv() const {
        std::string s;
        for (std::size_t k = 0; k < names.size(); ++k) {
            if (k) s += ",";
            s += csv_cell(names[k]);
        }
        s += "\n";
        for (std::size_t r = 0; r < rows(); ++r) {
            for (std::size_t k = 0; k < names.size(); ++k) {
                if (k) s += ",";
                if (types[k] == text)
                    s += csv_cell(strings[k][r]);
                else if (types[k] == integer)
                    s += std::to_string(integers[k][r]);
                else
                    s += num(numbers[k][r]);
            }
            s += "\n";
        }
        return s;
    }
    void hdf5(io::Hdf5Writer& w, const std::string& group, const std::string& what) const {
        for (std::size_t k = 0; k < names.size(); ++k) {
            const std::string path = group + "/" + names[k];
            if (types[k] == text)
                w.strings(path, strings[k], what + ": " + names[k]);
            else if (types[k] == integer)
                w.series(path, integers[k], unit_of(names[k]), what + ": " + names[k]);
            else
                w.series(path, numbers[k], unit_of(names[k]), what + ": " + names[k]);
        }
    }
};

struct Fit {
    bool valid = false;
    double intercept = 0, rate = 0, q = 0, r2 = 0;
};

/// Least-squares fit of ln N against the class middles over the non-empty classes.
Fit fit_histogram(const std::vector<double>& per_ha, double width) {
    std::vector<double> x, y;
    for (std::size_t i = 0; i < per_ha.size(); ++i)
        if (per_ha[i] > 0) {
            x.push_back((static_cast<double>(i) + 0.5) * width);
            y.push_back(std::log(per_ha[i]));
        }
    Fit f;
    if (x.size() < 3) return f;
    const double n = static_cast<double>(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
        sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i], syy += y[i] * y[i];
    const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
    const double slope = cxy / vx;
    f.valid = true;
    f.rate = -slope;
    f.intercept = (sy - slope * sx) / n;
    f.q = std::exp(f.rate * width);
    f.r2 = vy > 0 ? cxy * cxy / (vx * vy) : 0;
    return f;
}

struct Row {
    std::size_t index = 0;
    json record;
    json timing;
    bool ok = false;
};

std::string axis_text(const json& record, const std::string& key) {
    for (const auto& a : record.value("axes", json::array()))
        if (a.value("key", "") == key) return value_text(a["value"]);
    return "";
}

double axis_number(const json& record, const std::string& key) {
    for (const auto& a : record.value("axes", json::array()))
        if (a.value("key", "") == key && a["value"].is_number()) return a["value"].get<double>();
    return NAN;
}

double metric(const json& record, const std::string& name) {
    const json& m = record.value("metrics", json::object());
    if (!m.contains(name) || !m[name].is_number()) return NAN;
    return m[name].get<double>();
}

std::vector<double> histogram_of(const json& record, double& width) {
    std::vector<double> h;
    if (!record.contains("histogram")) return h;
    width = record["histogram"].value("class_width_cm", 5.0);
    for (const auto& v : record["histogram"]["stems_per_ha"]) h.push_back(v.get<double>());
    return h;
}

/// Mean (and sd) histogram of the rows; classes past a row's end count as empty.
std::pair<std::vector<double>, std::vector<double>>
mean_histogram(const std::vector<const Row*>& rows, double& width) {
    std::vector<std::vector<double>> hs;
    std::size_t classes = 0;
    for (const Row* r : rows) {
        hs.push_back(histogram_of(r->record, width));
        classes = std::max(classes, hs.back().size());
    }
    std::vector<double> mean(classes, 0.0), sd(classes, 0.0);
    if (hs.empty()) return {mean, sd};
    const double n = static_cast<double>(hs.size());
    for (auto& h : hs) h.resize(classes, 0.0);
    for (std::size_t i = 0; i < classes; ++i) {
        for (const auto& h : hs) mean[i] += h[i] / n;
        for (const auto& h : hs) sd[i] += (h[i] - mean[i]) * (h[i] - mean[i]);
        sd[i] = hs.size() > 1 ? std::sqrt(sd[i] / (n - 1)) : 0.0;
    }
    return {mean, sd};
}

void draw_pictures(const Manifest& m, const std::vector<Row>& rows, const fs::path& dir,
                   SummaryReport& rep) {
    for (const auto& p : m.pictures) {
        // Group the members that succeeded by the series' value (in the axis' order).
        std::vector<std::string> series_values{""};
        if (!p.series.empty()) {
            series_values.clear();
            for (const auto& a : m.axes)
                if (a.key == p.series)
                    for (const auto& v : a.values) series_values.push_back(value_text(v));
        }
        const fs::path file = dir / (p.name + ".png");
        const std::string title = p.title.empty() ? m.name : p.title;
        if (p.histogram) {
            std::vector<run::HistogramSeries> hs;
            double width = 5;
            std::size_t count = 0;
            for (const auto& sv : series_values) {
                std::vector<const Row*> sel;
                for (const auto& r : rows)
                    if (r.ok && (p.series.empty() || axis_text(r.record, p.series) == sv))
                        sel.push_back(&r);
                if (sel.empty()) continue;
                count = std::max(count, sel.size());
                run::HistogramSeries h;
                h.label = sv.empty() ? "all members" : sv;
                h.stems_per_ha = mean_histogram(sel, width).first;
                const Fit f = fit_histogram(h.stems_per_ha, width);
                h.fit = f.valid;
                h.intercept = f.intercept, h.rate_per_cm = f.rate, h.q_per_class = f.q, h.r2 = f.r2;
                hs.push_back(std::move(h));
            }
            run::draw_histogram_plot(hs, width, title,
                                     "mean of up to " + std::to_string(count) +
                                         " members per series; lines: negative-exponential fits "
                                         "of the means",
                                     file);
        } else {
            std::vector<run::PlotSeries> ps;
            std::vector<double> xs;
            for (const auto& a : m.axes)
                if (a.key == p.x)
                    for (const auto& v : a.values)
                        if (v.is_number()) xs.push_back(v.get<double>());
            std::size_t per_point = 0;
            for (const auto& sv : series_values) {
                run::PlotSeries s;
                s.label = sv.empty() ? p.y : sv;
                for (double x : xs) {
                    std::vector<double> ys;
                    for (const auto& r : rows)
                        if (r.ok && axis_number(r.record, p.x) == x &&
                            (p.series.empty() || axis_text(r.record, p.series) == sv))
                            ys.push_back(metric(r.record, p.y));
                    const Stats st = stats(ys);
                    if (st.n == 0) continue;
                    per_point = std::max(per_point, st.n);
                    s.x.push_back(x * p.x_scale);
                    s.y.push_back(st.mean);
                    s.lo.push_back(st.p10);
                    s.hi.push_back(st.p90);
                }
                if (!s.x.empty()) ps.push_back(std::move(s));
            }
            const std::string unit = unit_of(p.y);
            run::draw_line_plot(ps, title, p.x_label.empty() ? p.x : p.x_label,
                                p.y_label.empty() ? p.y + (unit == "1" ? "" : " (" + unit + ")")
                                                  : p.y_label,
                                "points: mean of up to " + std::to_string(per_point) +
                                    " members; band: 10th to 90th percentile",
                                file);
        }
        rep.files.push_back(file);
    }
}

} // namespace

namespace {

/// The records of the finished members (the missing and failed ones counted in `rep`).
std::vector<Row> read_rows(const fs::path& out, const Manifest& m, SummaryReport& rep) {
    std::vector<Row> rows;
    for (std::size_t i = 0; i < m.members(); ++i) {
        auto r = read_member_record(out, m, i);
        if (!r) {
            rep.missing_members.push_back(i);
            continue;
        }
        Row row;
        row.index = i;
        row.record = std::move(*r);
        row.ok = row.record.value("status", "") == "ok";
        try {
            row.timing = json::parse(io::read_text(member_dir(out, m, i) / "timing.json"));
        } catch (const std::exception&) {
            row.timing = json::object();
        }
        if (row.ok) {
            ++rep.ok;
        } else {
            rep.failed_members.push_back(i);
            rep.failures.push_back("member " + std::to_string(i) + ": " +
                                   row.record.value("error", "failed"));
        }
        rows.push_back(std::move(row));
    }
    rep.failed = rep.failed_members.size();
    rep.missing = rep.missing_members.size();
    return rows;
}

/// Metric columns in the order they first appear.
std::vector<std::string> metric_names(const std::vector<Row>& rows) {
    std::vector<std::string> metrics;
    std::set<std::string> seen;
    for (const auto& r : rows)
        for (auto it = r.record["metrics"].begin(); it != r.record["metrics"].end(); ++it)
            if (seen.insert(it.key()).second) metrics.push_back(it.key());
    return metrics;
}

/// One row per finished member: its axes, metrics and timing.
Columns members_table(const Manifest& m, const std::vector<Row>& rows,
                      const std::vector<std::string>& metrics) {
    Columns mt;
    using C = Columns;
    const auto c_member = mt.add("member", C::integer), c_comb = mt.add("combination", C::integer),
               c_rep = mt.add("replicate", C::integer), c_seed = mt.add("seed", C::integer),
               c_status = mt.add("status", C::text);
    std::vector<std::size_t> c_axes;
    for (const auto& a : m.axes) c_axes.push_back(mt.add(a.key, C::text));
    std::vector<std::size_t> c_metrics;
    for (const auto& k : metrics) c_metrics.push_back(mt.add(k, C::number));
    const auto c_sec = mt.add("seconds", C::number), c_threads = mt.add("threads", C::integer),
               c_host = mt.add("host", C::text), c_err = mt.add("error", C::text);
    for (const auto& r : rows) {
        mt.integers[c_member].push_back(static_cast<std::int64_t>(r.index));
        mt.integers[c_comb].push_back(r.record.value("combination", std::int64_t{0}));
        mt.integers[c_rep].push_back(r.record.value("replicate", std::int64_t{0}));
        mt.integers[c_seed].push_back(r.record.value("seed", std::int64_t{0}));
        mt.strings[c_status].push_back(r.record.value("status", ""));
        for (std::size_t k = 0; k < m.axes.size(); ++k)
            mt.strings[c_axes[k]].push_back(axis_text(r.record, m.axes[k].key));
        for (std::size_t k = 0; k < metrics.size(); ++k)
            mt.numbers[c_metrics[k]].push_back(metric(r.record, metrics[k]));
        mt.numbers[c_sec].push_back(r.timing.value("seconds", NAN));
        mt.integers[c_threads].push_back(r.timing.value("threads", std::int64_t{0}));
        mt.strings[c_host].push_back(r.timing.value("host", ""));
        mt.strings[c_err].push_back(r.record.value("error", ""));
    }
    return mt;
}

/// The aggregate table (one row per combination: statistics of each metric over its ok members
/// and, for run bases, the fit of the mean histogram) and the mean histograms.
class Aggregates {
public:
    Aggregates(const Manifest& m, const std::vector<std::string>& metrics, bool histograms);
    /// Adds combination `c` of the members `sel`.
    void add(std::size_t c, const std::vector<const Row*>& sel);
    Columns ag, hg;

private:
    void add_histogram(std::size_t c, const Member& first, const std::vector<const Row*>& good);
    const Manifest& m_m;
    const std::vector<std::string>& m_metrics;
    bool m_histograms;
    std::size_t a_comb, a_members, a_ok, a_failed, a_fit_q = 0, a_fit_r2 = 0;
    std::vector<std::size_t> a_axes, h_axes;
    std::vector<std::array<std::size_t, 5>> a_metrics;
    std::size_t h_comb, h_lo, h_hi, h_mean, h_sd;
};

Aggregates::Aggregates(const Manifest& m, const std::vector<std::string>& metrics, bool histograms)
    : m_m(m), m_metrics(metrics), m_histograms(histograms) {
    using C = Columns;
    a_comb = ag.add("combination", C::integer);
    for (const auto& a : m.axes) a_axes.push_back(ag.add(a.key, C::text));
    a_members = ag.add("members", C::integer);
    a_ok = ag.add("ok", C::integer);
    a_failed = ag.add("failed", C::integer);
    for (const auto& k : metrics)
        a_metrics.push_back({ag.add(k + ".mean", C::number), ag.add(k + ".sd", C::number),
                             ag.add(k + ".p10", C::number), ag.add(k + ".p50", C::number),
                             ag.add(k + ".p90", C::number)});
    if (histograms) {
        a_fit_q = ag.add("histogram.fit_q_per_class", C::number);
        a_fit_r2 = ag.add("histogram.fit_r2", C::number);
    }
    h_comb = hg.add("combination", C::integer);
    for (const auto& a : m.axes) h_axes.push_back(hg.add(a.key, C::text));
    h_lo = hg.add("class_lower_cm", C::number);
    h_hi = hg.add("class_upper_cm", C::number);
    h_mean = hg.add("mean_stems_per_ha", C::number);
    h_sd = hg.add("sd_stems_per_ha", C::number);
}

void Aggregates::add(std::size_t c, const std::vector<const Row*>& sel) {
    const Member first = make_member(m_m, c * static_cast<std::size_t>(m_m.replicates));
    std::vector<const Row*> good;
    for (const Row* r : sel)
        if (r->ok) good.push_back(r);
    ag.integers[a_comb].push_back(static_cast<std::int64_t>(c));
    for (std::size_t k = 0; k < m_m.axes.size(); ++k)
        ag.strings[a_axes[k]].push_back(value_text(first.axes[k].second));
    ag.integers[a_members].push_back(m_m.replicates);
    ag.integers[a_ok].push_back(static_cast<std::int64_t>(good.size()));
    ag.integers[a_failed].push_back(static_cast<std::int64_t>(sel.size() - good.size()));
    for (std::size_t k = 0; k < m_metrics.size(); ++k) {
        std::vector<double> v;
        for (const Row* r : good) v.push_back(metric(r->record, m_metrics[k]));
        const Stats s = stats(v);
        const double vals[5] = {s.mean, s.sd, s.p10, s.p50, s.p90};
        for (int q = 0; q < 5; ++q) ag.numbers[a_metrics[k][q]].push_back(vals[q]);
    }
    if (m_histograms) add_histogram(c, first, good);
}

void Aggregates::add_histogram(std::size_t c, const Member& first,
                               const std::vector<const Row*>& good) {
    double width = 5;
    const auto [mean, sd] = mean_histogram(good, width);
    const Fit f = fit_histogram(mean, width);
    ag.numbers[a_fit_q].push_back(f.valid ? f.q : NAN);
    ag.numbers[a_fit_r2].push_back(f.valid ? f.r2 : NAN);
    for (std::size_t i = 0; i < mean.size(); ++i) {
        hg.integers[h_comb].push_back(static_cast<std::int64_t>(c));
        for (std::size_t k = 0; k < m_m.axes.size(); ++k)
            hg.strings[h_axes[k]].push_back(value_text(first.axes[k].second));
        hg.numbers[h_lo].push_back(static_cast<double>(i) * width);
        hg.numbers[h_hi].push_back(static_cast<double>(i + 1) * width);
        hg.numbers[h_mean].push_back(mean[i]);
        hg.numbers[h_sd].push_back(sd[i]);
    }
}

/// The paired table: replicate r of every combination shares its seeds (terrain, weather,
/// lines), so the change of a metric from one value of an axis to the next, all other axes
/// fixed, can be taken replicate by replicate. One row per combination and axis whose value is
/// not the axis's first: the number of replicates ok at both, and the mean, standard deviation
/// and standard error of each metric's change. Empty when seeds are per member or one replicate.
Columns paired_table(const Manifest& m, const std::vector<std::string>& metrics,
                     const std::map<std::size_t, const Row*>& by_member) {
    using C = Columns;
    Columns t;
    if (m.seed_per_member || m.replicates < 2 || m.axes.empty()) return t;
    const std::size_t c_comb = t.add("combination", C::integer),
                      c_from = t.add("from_combination", C::integer),
                      c_axis = t.add("axis", C::text), c_fromv = t.add("from", C::text),
                      c_to = t.add("to", C::text), c_pairs = t.add("pairs", C::integer);
    std::vector<std::size_t> c_axes;
    for (const auto& a : m.axes) c_axes.push_back(t.add(a.key, C::text));
    std::vector<std::array<std::size_t, 3>> c_m;
    for (const auto& k : metrics)
        c_m.push_back({t.add(k + ".change_mean", C::number), t.add(k + ".change_sd", C::number),
                       t.add(k + ".change_se", C::number)});
    // Combination c's index along axis k: the last axis turns fastest.
    std::vector<std::size_t> stride(m.axes.size(), 1);
    for (std::size_t k = m.axes.size() - 1; k > 0; --k)
        stride[k - 1] = stride[k] * m.axes[k].values.size();
    const auto reps = static_cast<std::size_t>(m.replicates);
    auto row_of = [&](std::size_t comb, std::size_t r) -> const Row* {
        const auto it = by_member.find(comb * reps + r);
        return it != by_member.end() && it->second->ok ? it->second : nullptr;
    };
    for (std::size_t c = 0; c < m.combinations(); ++c)
        for (std::size_t k = 0; k < m.axes.size(); ++k) {
            const std::size_t i = c / stride[k] % m.axes[k].values.size();
            if (i == 0) continue;
            const std::size_t from = c - stride[k];
            const Member first = make_member(m, c * reps);
            t.integers[c_comb].push_back(static_cast<std::int64_t>(c));
            t.integers[c_from].push_back(static_cast<std::int64_t>(from));
            t.strings[c_axis].push_back(m.axes[k].key);
            t.strings[c_fromv].push_back(value_text(m.axes[k].values[i - 1]));
            t.strings[c_to].push_back(value_text(m.axes[k].values[i]));
            for (std::size_t a = 0; a < m.axes.size(); ++a)
                t.strings[c_axes[a]].push_back(value_text(first.axes[a].second));
            std::int64_t pairs = 0;
            for (std::size_t r = 0; r < reps; ++r) pairs += row_of(c, r) && row_of(from, r);
            t.integers[c_pairs].push_back(pairs);
            for (std::size_t q = 0; q < metrics.size(); ++q) {
                std::vector<double> d;
                for (std::size_t r = 0; r < reps; ++r) {
                    const Row *a = row_of(from, r), *b = row_of(c, r);
                    if (!a || !b) continue;
                    const double x = metric(b->record, metrics[q]) - metric(a->record, metrics[q]);
                    if (std::isfinite(x)) d.push_back(x);
                }
                const Stats st = stats(d);
                t.numbers[c_m[q][0]].push_back(st.mean);
                t.numbers[c_m[q][1]].push_back(st.sd);
                t.numbers[c_m[q][2]].push_back(
                    d.size() > 1 ? st.sd / std::sqrt(static_cast<double>(d.size())) : NAN);
            }
        }
    return t;
}

/// The tables as CSV and in summary.h5; the files are added to `rep`.
void write_tables(const fs::path& dir, const Manifest& m, const Columns& mt, const Aggregates& a,
                  const Columns& paired, bool histograms, SummaryReport& rep) {
    io::create_folder(dir, "the summary folder");
    io::write_text_atomic(dir / "members.csv", mt.csv());
    io::write_text_atomic(dir / "aggregate.csv", a.ag.csv());
    rep.files = {dir / "members.csv", dir / "aggregate.csv"};
    if (paired.rows() > 0) {
        io::write_text_atomic(dir / "paired.csv", paired.csv());
        rep.files.push_back(dir / "paired.csv");
    }
    if (histograms) {
        io::write_text_atomic(dir / "histograms.csv", a.hg.csv());
        rep.files.push_back(dir / "histograms.csv");
    }
    io::Hdf5Writer w(dir / "summary.h5");
    w.attribute("/", "ensemble", m.name);
    w.attribute("/", "description", m.description);
    w.integer_attribute("/", "members", static_cast<std::int64_t>(m.members()));
    w.integer_attribute("/", "ok", static_cast<std::int64_t>(rep.ok));
    w.integer_attribute("/", "failed", static_cast<std::int64_t>(rep.failed));
    w.integer_attribute("/", "missing", static_cast<std::int64_t>(rep.missing));
    mt.hdf5(w, "/members", "one row per finished member");
    a.ag.hdf5(w, "/aggregate", "one row per combination of axis values");
    if (histograms) a.hg.hdf5(w, "/histograms", "mean diameter histogram per combination");
    if (paired.rows() > 0)
        paired.hdf5(w, "/paired",
                    "change of each metric to the next value of an axis, replicate by replicate");
    w.commit();
    rep.files.push_back(dir / "summary.h5");
}

/// The stochastic mobility map of one combination: over its members' maps, per cell the
/// probability of GO (in at least one heading), the mean share of headings GO and the 10th, 50th
/// and 90th percentiles of the mean speed; nothing when the members' grids differ.
void write_stochastic_map(const fs::path& out, const Manifest& m, std::size_t c,
                          const std::vector<const Row*>& rows, const fs::path& dir,
                          SummaryReport& rep) {
    std::vector<RasterD> speed, go;
    for (const Row* r : rows) {
        if (!r->ok) continue;
        const fs::path md = member_dir(out, m, r->index) / "mobility_map";
        speed.push_back(terrain::io::read_raster(md / "speed_mean_m_per_s.tif"));
        go.push_back(terrain::io::read_raster(md / "go_fraction.tif"));
        const GridSpec &a = speed.front().grid(), &b = speed.back().grid();
        if (a.nx != b.nx || a.ny != b.ny || a.cell_size_m != b.cell_size_m) {
            rep.failures.push_back("combination " + std::to_string(c) +
                                   ": no stochastic map (the members' map grids differ)");
            return;
        }
    }
    if (speed.empty()) return;
    const GridSpec g = speed.front().grid();
    RasterD p_go(g, 0.0), share(g, 0.0), p10(g, 0.0), p50(g, 0.0), p90(g, 0.0);
    std::vector<double> v(speed.size());
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            for (std::size_t k = 0; k < speed.size(); ++k) {
                v[k] = speed[k](i, j);
                p_go(i, j) += go[k](i, j) > 0 ? 1.0 : 0.0;
                share(i, j) += go[k](i, j);
            }
            p_go(i, j) /= static_cast<double>(speed.size());
            share(i, j) /= static_cast<double>(speed.size());
            std::sort(v.begin(), v.end());
            p10(i, j) = quantile(v, 0.1);
            p50(i, j) = quantile(v, 0.5);
            p90(i, j) = quantile(v, 0.9);
        }
    char prefix[48];
    std::snprintf(prefix, sizeof prefix, "combination_%03zu_", c);
    const fs::path maps = dir / "maps";
    io::create_folder(maps, "the summary's map folder");
    auto layer = [&](RasterD& r, const std::string& name, const std::string& units) {
        r.set_crs_wkt(speed.front().crs_wkt());
        const fs::path f = maps / (prefix + name);
        terrain::io::write_geotiff(r, f, units);
        rep.files.push_back(f);
    };
    layer(p_go, "go_probability.tif", "1");
    layer(share, "go_share_of_headings_mean.tif", "1");
    layer(p10, "speed_p10_m_per_s.tif", "m/s");
    layer(p50, "speed_p50_m_per_s.tif", "m/s");
    layer(p90, "speed_p90_m_per_s.tif", "m/s");
    terrain::MapFigure f;
    f.title = "Probability of GO, combination " + std::to_string(c) + " (" +
              std::to_string(speed.size()) + " members)";
    f.bar_label = "probability of GO";
    f.smooth = false;
    const fs::path png = maps / (std::string(prefix) + "go_probability.png");
    terrain::write_map_figure(terrain::colormap_image(p_go, 0.0, 1.0), g, f, png);
    rep.files.push_back(png);
}

} // namespace

SummaryReport write_summary(const fs::path& out, const Manifest& m) {
    SummaryReport rep;
    rep.members = m.members();
    const std::vector<Row> rows = read_rows(out, m, rep);
    const std::vector<std::string> metrics = metric_names(rows);
    const Columns mt = members_table(m, rows, metrics);
    const bool histograms = m.kind == BaseKind::run;
    Aggregates a(m, metrics, histograms);
    std::map<std::size_t, std::vector<const Row*>> by_comb;
    for (const auto& r : rows) by_comb[r.record.value("combination", std::size_t{0})].push_back(&r);
    for (std::size_t c = 0; c < m.combinations(); ++c) a.add(c, by_comb[c]);
    std::map<std::size_t, const Row*> by_member;
    for (const auto& r : rows) by_member[r.index] = &r;
    const Columns paired = paired_table(m, metrics, by_member);
    const fs::path dir = out / "summary";
    write_tables(dir, m, mt, a, paired, histograms, rep);
    draw_pictures(m, rows, dir, rep);
    if (m.analyses.contains("mobility_map"))
        for (std::size_t c = 0; c < m.combinations(); ++c)
            write_stochastic_map(out, m, c, by_comb[c], dir, rep);
    return rep;
}

} // namespace ecoterra::ensemble
