// `ecoterra ensemble` as users run it: the same members whatever the number of processes (and
// under mpirun), resuming after kill -9, failing members reported, bad input refused.
#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "support/run_cli.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <set>
#include <thread>

using namespace ecoterra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// A small ensemble over the quickstart scene cut to 0.25 ha: 2 x 2 combinations x 2 replicates,
/// with the stand and MRZR mobility of every member.
json small_manifest(const std::string& name = "small") {
    const std::string data = test::data_dir().string();
    return {{"name", name},
            {"base", {{"run", data + "/scenes/quickstart.json"}}},
            {"seed", 5},
            {"replicates", 2},
            {"keep_files", true},
            {"set",
             {{"terrain.generate.size", 25},
              {"simulation.years", 12},
              {"simulation.snapshot_interval_years", 6}}},
            {"axes",
             {{{"key", "vegetation.competition"}, {"values", {"coupled", "light_only"}}},
              {{"key", "soil.random.patch_size_m"}, {"values", {20, 40}}}}},
            {"analyses",
             {{"stand", json::object()},
              {"mobility", {{"vehicle", data + "/vehicles/mrzr4.json"}, {"lines", 20}}}}},
            {"pictures",
             {{{"name", "smg"},
               {"x", "soil.random.patch_size_m"},
               {"y", "mobility.smg_mean_m_per_s"},
               {"series", "vegetation.competition"}},
              {{"name", "hist"}, {"histogram", true}}}}};
}

void write(const fs::path& p, const json& j) {
    io::write_text_atomic(p, j.dump(1));
}

/// Every file under `dir` (relative path -> bytes), leaving out the run-dependent timing.json and
/// the logs.
std::map<std::string, std::string> member_files(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir / "members")) {
        if (!e.is_regular_file() || e.path().filename() == "timing.json") continue;
        out[fs::relative(e.path(), dir).string()] = io::read_text(e.path());
    }
    return out;
}

json record(const fs::path& dir, int member) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d", member);
    return json::parse(io::read_text(dir / "members" / name / "member.json"));
}

/// Rows of a CSV as maps column -> text (RFC 4180 quoting: "..." with "" inside).
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
    const std::string text = io::read_text(p);
    std::vector<std::vector<std::string>> table(1);
    std::string cell;
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                cell += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                cell += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            table.back().push_back(cell);
            cell.clear();
        } else if (c == '\n') {
            table.back().push_back(cell);
            cell.clear();
            table.emplace_back();
        } else {
            cell += c;
        }
    }
    if (table.back().empty()) table.pop_back();
    std::vector<std::map<std::string, std::string>> rows;
    for (std::size_t r = 1; r < table.size(); ++r) {
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < table[0].size() && k < table[r].size(); ++k)
            row[table[0][k]] = table[r][k];
        rows.push_back(row);
    }
    return rows;
}

} // namespace

TEST_CASE("ensemble: members are the same bytes with 1 or 2 processes and under mpirun",
          "[ensemble][cli][slow]") {
    test::TempDir d;
    write(d / "m.json", small_manifest());
    const auto one = test::run(d, "ensemble m.json -o out --jobs 1");
    INFO(one.out);
    REQUIRE(one.code == 0);
    CHECK_THAT(one.out, Catch::Contains("8 of 8 members ok, 0 failed, 0 not run"));
    const auto a = member_files(d.path() / "out");
    // run.h5, its snapshots, stand.json, mobility.json, member.json per member
    CHECK(a.size() == 8 * 6);
    fs::rename(d / "out", d / "out-jobs1");
    const auto two = test::run(d, "ensemble m.json -o out --jobs 2");
    INFO(two.out);
    REQUIRE(two.code == 0);
    CHECK(member_files(d.path() / "out") == a);
#ifdef ECOTERRA_MPIRUN
    fs::rename(d / "out", d / "out-jobs2");
    const auto mpi =
        test::shell(d, ECOTERRA_MPIRUN " --allow-run-as-root --oversubscribe -np 3 '" ECOTERRA_BIN
                                       "' ensemble m.json -o out");
    INFO(mpi.out);
    REQUIRE(mpi.code == 0);
    CHECK_THAT(mpi.out, Catch::Contains("2 worker ranks") && Catch::Contains("rank 0 spent"));
    CHECK(member_files(d.path() / "out") == a);
#endif
    // Every member records its axes and its seed; replicate r shares its seeds across the axes.
    std::map<int, std::uint64_t> seed_of_replicate;
    for (int i = 0; i < 8; ++i) {
        const json r = record(d.path() / "out", i);
        CHECK(r["status"] == "ok");
        CHECK(r["member"] == i);
        CHECK(r["replicate"] == i % 2);
        const auto s = r["seed"].get<std::uint64_t>();
        CHECK(r["seeds"]["simulation.seed"].get<std::uint64_t>() == s);
        if (seed_of_replicate.count(i % 2))
            CHECK(seed_of_replicate[i % 2] == s);
        else
            seed_of_replicate[i % 2] = s;
    }
    CHECK(seed_of_replicate[0] != seed_of_replicate[1]);
}

TEST_CASE("ensemble: the summary is the members' figures, gathered", "[ensemble][cli][slow]") {
    test::TempDir d;
    write(d / "m.json", small_manifest());
    REQUIRE(test::run(d, "ensemble m.json -o out").code == 0);
    const auto members = read_csv(d / "out/summary/members.csv");
    REQUIRE(members.size() == 8);
    for (const auto& row : members) {
        const json r = record(d.path() / "out", std::stoi(row.at("member")));
        CHECK(row.at("status") == "ok");
        CHECK(row.at("vegetation.competition") == r["axes"][0]["value"].get<std::string>());
        CHECK(std::stod(row.at("mobility.smg_mean_m_per_s")) ==
              Approx(r["metrics"]["mobility.smg_mean_m_per_s"].get<double>()).epsilon(1e-15));
        CHECK(std::stoull(row.at("seed")) == r["seed"].get<std::uint64_t>());
        // One name and one value everywhere: each catalogued metric of the member is the
        // top-level key of the same name in the analysis's JSON (as the program writes it).
        char name[16];
        std::snprintf(name, sizeof name, "%06d", std::stoi(row.at("member")));
        const fs::path dir = d.path() / "out/members" / name;
        const json stand = parse_json(io::read_text(dir / "stand.json"), "stand.json");
        const json mob = parse_json(io::read_text(dir / "mobility.json"), "mobility.json");
        auto same = [&](const std::string& analysis, const json& doc, const auto& metrics) {
            for (const auto& c : metrics) {
                CAPTURE(analysis, c.name);
                const std::string key = c.name;
                const json& v = r["metrics"][analysis + "." + key];
                REQUIRE(doc.contains(key));
                const json& in_doc = doc[key];
                if (v.is_null())
                    CHECK(in_doc.is_null());
                else
                    CHECK(in_doc.get<double>() == v.get<double>());
            }
        };
        same("stand", stand, analyses::stand_metrics());
        same("mobility", mob, analyses::mobility_metrics());
    }
    // Aggregates: each combination's mean and extremes of its members.
    const auto agg = read_csv(d / "out/summary/aggregate.csv");
    REQUIRE(agg.size() == 4);
    for (const auto& row : agg) {
        std::vector<double> v;
        for (const auto& m : members)
            if (m.at("combination") == row.at("combination"))
                v.push_back(std::stod(m.at("stand.basal_area_m2_per_ha")));
        REQUIRE(v.size() == 2);
        CHECK(row.at("ok") == "2");
        CHECK(std::stod(row.at("stand.basal_area_m2_per_ha.mean")) ==
              Approx((v[0] + v[1]) / 2).epsilon(1e-12));
        CHECK(std::stod(row.at("stand.basal_area_m2_per_ha.p50")) ==
              Approx((v[0] + v[1]) / 2).epsilon(1e-12));
        CHECK(std::stod(row.at("stand.basal_area_m2_per_ha.sd")) ==
              Approx(std::abs(v[0] - v[1]) / std::sqrt(2.0)).epsilon(1e-9));
    }
    // The mean histogram per combination holds as many stems per ha as the members' mean.
    const auto hist = read_csv(d / "out/summary/histograms.csv");
    for (const auto& row : agg) {
        double sum = 0;
        for (const auto& h : hist)
            if (h.at("combination") == row.at("combination"))
                sum += std::stod(h.at("mean_stems_per_ha"));
        CHECK(sum == Approx(std::stod(row.at("stand.stems_per_ha.mean"))).epsilon(1e-9));
    }
    // Paired changes: replicate r of each combination shares its seeds, so the change to the
    // next value of an axis is taken replicate by replicate (2 axes of 2 values: 4 rows).
    const auto paired = read_csv(d / "out/summary/paired.csv");
    REQUIRE(paired.size() == 4);
    auto member_value = [&](const std::string& comb, const std::string& rep) {
        for (const auto& m : members)
            if (m.at("combination") == comb && m.at("replicate") == rep)
                return std::stod(m.at("stand.basal_area_m2_per_ha"));
        FAIL("no member " << comb << "/" << rep);
        return 0.0;
    };
    std::set<std::string> axes_seen;
    for (const auto& row : paired) {
        CHECK(row.at("pairs") == "2");
        axes_seen.insert(row.at("axis"));
        CHECK(row.at(row.at("axis")) == row.at("to"));
        CHECK(row.at("from") != row.at("to"));
        const double d0 = member_value(row.at("combination"), "0") -
                          member_value(row.at("from_combination"), "0"),
                     d1 = member_value(row.at("combination"), "1") -
                          member_value(row.at("from_combination"), "1");
        CHECK(std::stod(row.at("stand.basal_area_m2_per_ha.change_mean")) ==
              Approx((d0 + d1) / 2).epsilon(1e-12).margin(1e-12));
        CHECK(std::stod(row.at("stand.basal_area_m2_per_ha.change_sd")) ==
              Approx(std::abs(d0 - d1) / std::sqrt(2.0)).epsilon(1e-9).margin(1e-12));
        CHECK(std::stod(row.at("stand.basal_area_m2_per_ha.change_se")) ==
              Approx(std::abs(d0 - d1) / 2).epsilon(1e-9).margin(1e-12));
    }
    CHECK(axes_seen == std::set<std::string>{"vegetation.competition", "soil.random.patch_size_m"});
    for (const char* f : {"summary.h5", "smg.png", "hist.png"})
        CHECK(fs::file_size(d / "out/summary" / f) > 1000);
    // --summary gathers the same tables again from the folder alone.
    const std::string before = io::read_text(d / "out/summary/aggregate.csv");
    fs::remove(d / "out/summary/aggregate.csv");
    const auto s = test::run(d, "ensemble --summary out");
    INFO(s.out);
    CHECK(s.code == 0);
    CHECK(io::read_text(d / "out/summary/aggregate.csv") == before);
}

TEST_CASE("ensemble: a failing member is reported and the others complete", "[ensemble][cli]") {
    test::TempDir d;
    json m = small_manifest();
    m["axes"][0]["values"] = {"coupled", "geometric"};
    write(d / "m.json", m);
    const auto r = test::run(d, "ensemble m.json -o out");
    INFO(r.out);
    CHECK(r.code == 1);
    CHECK_THAT(r.out, Catch::Contains("4 of 8 members ok, 4 failed"));
    CHECK_THAT(r.out, Catch::Contains("--array=4-7"));
    for (int i = 0; i < 8; ++i) {
        const json rec = record(d.path() / "out", i);
        CHECK(rec["status"] == (i < 4 ? "ok" : "failed"));
        if (i >= 4) {
            CHECK_THAT(rec["error"].get<std::string>(),
                       Catch::Contains("vegetation.competition") && Catch::Contains("geometric"));
            // Nothing half-made beside a failed record.
            char name[16];
            std::snprintf(name, sizeof name, "%06d", i);
            CHECK_FALSE(fs::exists(d / "out/members" / name / "run.h5"));
        }
    }
    const auto rows = read_csv(d / "out/summary/members.csv");
    REQUIRE(rows.size() == 8);
    CHECK(rows[5].at("status") == "failed");
    CHECK_THAT(rows[5].at("error"), Catch::Contains("geometric"));
    CHECK(read_csv(d / "out/summary/aggregate.csv")[2].at("failed") == "2");
    // One member alone (a Slurm array task) runs the same and fails the same.
    const auto one = test::run(d, "ensemble m.json -o out --member 5");
    CHECK(one.code == 1);
    CHECK_THAT(one.out, Catch::Contains("member 5 of small: failed"));
}

TEST_CASE("ensemble: after kill -9 of the driver or of a member, running again completes it",
          "[ensemble][cli][slow]") {
    test::TempDir d;
    json m = small_manifest("slow");
    m["replicates"] = 1;                    // 4 members
    m["set"]["terrain.generate.size"] = 50; // 1 ha, 40 years: a second or two per member
    m["set"]["simulation.years"] = 40;
    m["set"]["simulation.snapshot_interval_years"] = 5;
    write(d / "m.json", m);
    const fs::path out = d / "out";
    // Up to 5 minutes: under the sanitizers, beside the rest of the suite on 2 cores, the three
    // members left after a kill take over a minute.
    auto wait_for = [&](const std::function<bool()>& f) {
        for (int k = 0; k < 3000 && !f(); ++k)
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        return f();
    };
    // The driver in the background; kill -9 once the first member is in place.
    REQUIRE(test::shell(d,
                        "('" ECOTERRA_BIN "' ensemble m.json -o out --jobs 2 > driver.log 2>&1 & "
                        "echo $! > driver.pid)")
                .code == 0);
    REQUIRE(wait_for([&] { return fs::exists(out / "members/000000/member.json"); }));
    const std::string pid = io::read_text(d / "driver.pid");
    test::shell(d, "kill -9 " + pid);
    // Its member processes finish or are killed too (here: killed, as a crashed node would).
    // Only this test's members: their command lines hold this test's folder (other tests run
    // ensembles at the same time). The [e] keeps the pattern from matching the shell running it.
    const std::string mine = d.path().string() + "/out --member";
    test::shell(d, "pkill -9 -f '[e]nsemble .* -o " + mine + "' || true");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::string kept = io::read_text(out / "members/000000/member.json");
    const std::string kept_timing = io::read_text(out / "members/000000/timing.json");
    auto second = test::run(d, "ensemble m.json -o out --jobs 2");
    INFO(second.out);
    CHECK(second.code == 0);
    CHECK_THAT(second.out, Catch::Contains("4 of 4 members ok"));
    CHECK_THAT(second.out, !Catch::Contains("0 done before"));
    // The member finished before the kill is untouched (its timing names the first run's process).
    CHECK(io::read_text(out / "members/000000/member.json") == kept);
    CHECK(io::read_text(out / "members/000000/timing.json") == kept_timing);
    // No staging folder is left behind or counted.
    for (const auto& e : fs::directory_iterator(out / "members"))
        CHECK(e.path().filename().string().find("partial") == std::string::npos);

    // kill -9 of one member: the driver records it as failed with the signal, the rest go on.
    fs::rename(out, d / "out-first");
    REQUIRE(test::shell(d,
                        "('" ECOTERRA_BIN "' ensemble m.json -o out --jobs 1 > driver2.log 2>&1 & "
                        "echo $! > driver2.pid)")
                .code == 0);
    const std::string member0 = "'[-]o " + mine + " 0 '";
    REQUIRE(wait_for([&] { return test::shell(d, "pgrep -f " + member0).code == 0; }));
    test::shell(d, "pkill -9 -f " + member0);
    REQUIRE(wait_for([&] { return fs::exists(out / "summary/members.csv"); }));
    REQUIRE(wait_for(
        [&] { return test::shell(d, "kill -0 $(cat driver2.pid) 2>/dev/null").code != 0; }));
    const json crashed = record(out, 0);
    CHECK(crashed["status"] == "failed");
    CHECK_THAT(crashed["error"].get<std::string>(), Catch::Contains("killed by signal 9"));
    CHECK_THAT(io::read_text(d / "driver2.log"), Catch::Contains("3 of 4 members ok, 1 failed"));
    const auto third = test::run(d, "ensemble m.json -o out");
    INFO(third.out);
    CHECK(third.code == 0);
    CHECK_THAT(third.out, Catch::Contains("3 done before, 1 to run"));
    CHECK(record(out, 0)["status"] == "ok");
    // The resumed ensemble's members are those of the uninterrupted one.
    CHECK(member_files(out) == member_files(d / "out-first"));
}

TEST_CASE("ensemble: a finished ensemble runs nothing again and a changed input reruns its members",
          "[ensemble][cli][slow]") {
    test::TempDir d;
    json m = small_manifest();
    write(d / "m.json", m);
    REQUIRE(test::run(d, "ensemble m.json -o out").code == 0);
    const std::string timing = io::read_text(d / "out/members/000003/timing.json");
    const auto again = test::run(d, "ensemble m.json -o out");
    CHECK(again.code == 0);
    CHECK_THAT(again.out, Catch::Contains("8 done before, 0 to run"));
    CHECK(io::read_text(d / "out/members/000003/timing.json") == timing);
    // More lines in the mobility analysis: every member's inputs changed.
    m["analyses"]["mobility"]["lines"] = 21;
    write(d / "m.json", m);
    const auto changed = test::run(d, "ensemble m.json -o out");
    CHECK_THAT(changed.out, Catch::Contains("0 done before, 8 to run"));
    CHECK(record(d.path() / "out", 3)["metrics"].contains("mobility.smg_mean_m_per_s"));
}

TEST_CASE("ensemble: bad input gets a clear error and loses nothing", "[ensemble][cli]") {
    test::TempDir d;
    write(d / "m.json", small_manifest());
    json other = small_manifest("other");
    write(d / "other.json", other);
    REQUIRE(test::run(d, "ensemble m.json -o out --member 2").code == 0);
    const std::string kept = io::read_text(d / "out/members/000002/member.json");
    struct Case {
        std::string args;
        std::vector<std::string> says;
    };
    const std::vector<Case> cases{
        {"ensemble other.json -o out",
         {"-o out holds the members of ensemble 'small'", "m.json", "not of 'other' (other.json)"}},
        {"ensemble m.json -o out --member 8", {"--member 8 is out of range", "members 0 to 7"}},
        {"ensemble m.json -o out --member -3", {"--member -3 is out of range"}},
        {"ensemble m.json", {"-o DIR"}},
        {"ensemble m.json -o m.json", {"-o m.json"}},
        {"ensemble m.json -o out --jobs -1", {"--jobs -1"}},
        {"ensemble missing.json -o x", {"missing.json"}},
        {"ensemble --summary nowhere", {"nowhere", "ensemble.json"}},
    };
    for (const auto& c : cases) {
        const auto r = test::run(d, c.args);
        INFO(c.args + "\n" + r.out);
        CHECK(r.code == 2);
        for (const auto& s : c.says) CHECK_THAT(r.out, Catch::Contains(s));
    }
    // Numbers past an integer's range, and a missing vehicle, are refused up front (exit 2,
    // nothing created); they once became -9223372036854775808, or failed every member (exit 1).
    json huge = small_manifest();
    huge["replicates"] = 1e300;
    write(d / "huge.json", huge);
    json axis = small_manifest();
    axis["axes"][1] = {{"key", "simulation.years"}, {"values", {1e308, 2}}};
    axis["pictures"] = json::array();
    write(d / "axis.json", axis);
    json car = small_manifest();
    car["axes"].push_back({{"key", "analyses.mobility.vehicle"},
                           {"values", {car["analyses"]["mobility"]["vehicle"], "nope.json"}}});
    write(d / "car.json", car);
    json car2 = small_manifest();
    car2["analyses"]["mobility"]["vehicle"] = "../gone/vehicle.json";
    write(d / "car2.json", car2);
    const std::vector<Case> refused{
        {"ensemble huge.json -o h", {"replicates = 1e+300 is outside [1, 1000000]"}},
        {"ensemble car.json -o h",
         {"axes[2] (analyses.mobility.vehicle) = 'nope.json'", "cannot open"}},
        {"ensemble car2.json -o h",
         {"analyses.mobility.vehicle = '../gone/vehicle.json'", "cannot open"}},
    };
    for (const auto& c : refused) {
        const auto r = test::run(d, c.args);
        INFO(c.args + "\n" + r.out);
        CHECK(r.code == 2);
        for (const auto& s : c.says) CHECK_THAT(r.out, Catch::Contains(s));
        CHECK_FALSE(fs::exists(d / "h"));
    }
    auto listed = test::run(d, "ensemble axis.json --list");
    CHECK(listed.code == 0);
    CHECK_THAT(listed.out, Catch::Contains("1e+308"));
    CHECK_THAT(listed.out, !Catch::Contains("-9223372036854775808"));
    const auto one = test::run(d, "ensemble axis.json -o ax --member 0");
    CHECK_THAT(one.out, Catch::Contains("simulation.years = 1e+308 is outside [1, 10000]"));
    // An output folder the system refuses: a failure to write (exit 1) naming it, not an
    // internal error (exit 3).
    const auto ro = test::run(d, "ensemble m.json -o /proc/ecoterra-no-such/out");
    CHECK(ro.code == 1);
    CHECK_THAT(ro.out, Catch::Contains("/proc/ecoterra-no-such/out") &&
                           Catch::Contains("cannot create") && !Catch::Contains("internal"));
    // A folder of other files is not an ensemble's: refused, its files untouched.
    fs::create_directories(d / "mine");
    io::write_text_atomic(d / "mine/notes.txt", "mine");
    const auto r = test::run(d, "ensemble m.json -o mine");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("no ensemble.json"));
    CHECK(io::read_text(d / "mine/notes.txt") == "mine");
    CHECK(io::read_text(d / "out/members/000002/member.json") == kept);
}

TEST_CASE("ensemble: terrain and mobility bases", "[ensemble][cli][slow]") {
    test::TempDir d;
    const std::string data = test::data_dir().string();
    // Terrains: the multifractal at two D_high, analysed and driven over by the Husky.
    write(d / "t.json", {{"name", "terrains"},
                         {"base", {{"terrain", {{"preset", "majhor2023"}, {"size", 401}}}}},
                         {"replicates", 2},
                         {"keep_files", true},
                         {"axes", {{{"key", "params.d_high"}, {"values", {2.3, 2.6}}}}},
                         {"analyses",
                          {{"terrain", json::object()},
                           {"traverse",
                            {{"vehicle", data + "/vehicles/husky_a200.json"},
                             {"missions", 4},
                             {"length_m", 6}}}}}});
    const auto t = test::run(d, "ensemble t.json -o t");
    INFO(t.out);
    REQUIRE(t.code == 0);
    for (int i = 0; i < 4; ++i) {
        const json r = record(d.path() / "t", i);
        CHECK(r["metrics"]["traverse.missions"] == 4);
        const double low = r["metrics"]["terrain.low_pct"], semi = r["metrics"]["terrain.semi_pct"],
                     high = r["metrics"]["terrain.high_pct"];
        CHECK(low + semi + high == Approx(100).epsilon(1e-9));
    }
    // Replicate r shares its terrain seed across D_high; the member's terrain is the one
    // `terrain generate` makes with that seed (both stored as HDF5, float32).
    const json r0 = record(d.path() / "t", 0), r2 = record(d.path() / "t", 2);
    CHECK(r0["seed"] == r2["seed"]);
    CHECK(r0["seed"] != record(d.path() / "t", 1)["seed"]);
    const auto gen = test::run(d, "terrain generate --preset majhor2023 --size 401 --d-high 2.3 "
                                  "--seed " +
                                      std::to_string(r0["seed"].get<std::uint64_t>()) + " -o g.h5");
    REQUIRE(gen.code == 0);
    REQUIRE(test::run(d, "terrain convert g.h5 g.asc").code == 0);
    REQUIRE(test::run(d, "terrain convert t/members/000000/terrain.h5 m.asc").code == 0);
    CHECK(io::read_text(d / "g.asc") == io::read_text(d / "m.asc"));
    // The member's own specification, kept beside its figures, replays it without the manifest.
    REQUIRE(
        test::run(d, "terrain generate --config t/members/000000/terrain_spec.json -o s.h5").code ==
        0);
    REQUIRE(test::run(d, "terrain convert s.h5 s.asc").code == 0);
    CHECK(io::read_text(d / "s.asc") == io::read_text(d / "m.asc"));
    // A terrain too rough for any mission (no low cell): the member fails, unless the traverse
    // may drive fewer; then it keeps its class areas and reports no mission.
    json rough = {
        {"name", "rough"},
        {"base", {{"terrain", {{"preset", "majhor2023"}, {"size", 401}}}}},
        {"set", {{"params.relief_m", 5000.0}}},
        {"analyses",
         {{"terrain", json::object()},
          {"traverse",
           {{"vehicle", data + "/vehicles/husky_a200.json"}, {"missions", 4}, {"length_m", 6}}}}}};
    write(d / "rough.json", rough);
    const auto failed = test::run(d, "ensemble rough.json -o rough");
    CHECK(failed.code != 0);
    CHECK_THAT(io::read_text(d / "rough/members/000000/member.json"),
               Catch::Contains("no low-roughness"));
    rough["analyses"]["traverse"]["allow_fewer"] = true;
    write(d / "fewer.json", rough);
    const auto fewer = test::run(d, "ensemble fewer.json -o fewer");
    INFO(fewer.out);
    REQUIRE(fewer.code == 0);
    const json f = record(d.path() / "fewer", 0);
    CHECK(f["metrics"]["traverse.missions"] == 0);
    CHECK(f["metrics"]["traverse.success_rate"].is_null());
    CHECK(f["metrics"]["terrain.closed_low_pct"] == 0); // where missions start
    CHECK(f["metrics"]["terrain.high_pct"].get<double>() > 90);
    CHECK(json::parse(
              io::read_text(d / "fewer/members/000000/traverse.json"))["missions_requested"] == 4);
    // A stand given as a stem list over a DEM, driven by two vehicles.
    REQUIRE(
        test::run(d, "run " + data + "/scenes/quickstart.json -o run.h5 --years 15 --no-pictures")
            .code == 0);
    REQUIRE(test::run(d, "export vegetation run.h5 -o stems.csv").code == 0);
    REQUIRE(test::run(d, "terrain convert run.h5 dem.tif").code == 0);
    write(d / "mob.json",
          {{"name", "vehicles"},
           {"base", {{"mobility", {{"stems", "stems.csv"}, {"dem", "dem.tif"}}}}},
           {"axes",
            {{{"key", "analyses.mobility.vehicle"},
              {"values", {data + "/vehicles/mrzr4.json", data + "/vehicles/husky_a200.json"}}}}},
           {"analyses", {{"mobility", {{"vehicle", "none"}, {"lines", 30}}}}}});
    const auto mob = test::run(d, "ensemble mob.json -o mob");
    INFO(mob.out);
    REQUIRE(mob.code == 0);
    const double mrzr = record(d.path() / "mob", 0)["metrics"]["mobility.smg_mean_m_per_s"];
    const double husky = record(d.path() / "mob", 1)["metrics"]["mobility.smg_mean_m_per_s"];
    CHECK(husky < 1.01); // the Husky's top speed is 1 m/s
    CHECK(mrzr > 3 * husky);
    // The same figures as `ecoterra mobility` with the member's seed.
    const std::uint64_t seed = record(d.path() / "mob", 0)["seeds"]["analyses.mobility.seed"];
    const auto direct = test::run(d, "mobility --stems stems.csv --dem dem.tif --vehicle " + data +
                                         "/vehicles/mrzr4.json --lines 30 --seed " +
                                         std::to_string(seed) + " --json direct.json");
    REQUIRE(direct.code == 0);
    CHECK(json::parse(io::read_text(d / "direct.json"))["smg_mean_m_per_s"].get<double>() == mrzr);
}

TEST_CASE("ensemble: the stochastic mobility map of each combination is its members' maps, "
          "gathered",
          "[ensemble][cli][map]") {
    test::TempDir d;
    const std::string data = test::data_dir().string();
    json m = small_manifest("maps");
    m["replicates"] = 4;
    m["axes"] =
        json::array({{{"key", "vegetation.competition"}, {"values", {"coupled", "light_only"}}}});
    // The members share one terrain (its seed fixed), so that the cells line up; vegetation,
    // soil water and dead wood vary with each member's seed.
    m["set"]["terrain.generate.seed"] = 3;
    m["analyses"] = {{"mobility_map", {{"vehicle", data + "/vehicles/mrzr4.json"}}}};
    m["pictures"] = json::array();
    write(d / "m.json", m);
    const auto r = test::run(d, "ensemble m.json -o out");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const auto members = read_csv(d / "out/summary/members.csv");
    REQUIRE(members.size() == 8);
    for (int c = 0; c < 2; ++c) {
        CAPTURE(c);
        char prefix[64];
        std::snprintf(prefix, sizeof prefix, "out/summary/maps/combination_%03d_", c);
        const RasterD p =
            terrain::io::read_raster(d / (std::string(prefix) + "go_probability.tif"));
        const RasterD p10 =
            terrain::io::read_raster(d / (std::string(prefix) + "speed_p10_m_per_s.tif"));
        const RasterD p50 =
            terrain::io::read_raster(d / (std::string(prefix) + "speed_p50_m_per_s.tif"));
        const RasterD p90 =
            terrain::io::read_raster(d / (std::string(prefix) + "speed_p90_m_per_s.tif"));
        CHECK(fs::file_size(d / (std::string(prefix) + "go_probability.png")) > 1000);
        // Recomputed from the members' own layers.
        std::vector<RasterD> go, speed;
        for (const auto& row : members)
            if (std::stoi(row.at("combination")) == c) {
                char name[16];
                std::snprintf(name, sizeof name, "%06d", std::stoi(row.at("member")));
                const fs::path md = d.path() / "out/members" / name / "mobility_map";
                go.push_back(terrain::io::read_raster(md / "go_fraction.tif"));
                speed.push_back(terrain::io::read_raster(md / "speed_mean_m_per_s.tif"));
            }
        REQUIRE(go.size() == 4);
        for (int j = 0; j < p.ny(); ++j)
            for (int i = 0; i < p.nx(); ++i) {
                double n = 0, lo = 1e9, hi = -1e9;
                for (std::size_t k = 0; k < go.size(); ++k) {
                    n += go[k](i, j) > 0 ? 1 : 0;
                    lo = std::min(lo, speed[k](i, j));
                    hi = std::max(hi, speed[k](i, j));
                }
                CHECK(p(i, j) == Approx(n / 4));
                CHECK(p10(i, j) >= lo - 1e-6);
                CHECK(p10(i, j) <= p50(i, j) + 1e-6);
                CHECK(p50(i, j) <= p90(i, j) + 1e-6);
                CHECK(p90(i, j) <= hi + 1e-6);
            }
    }
    // A manifest's mobility_map without a vehicle is refused before any member runs.
    m["analyses"]["mobility_map"].erase("vehicle");
    write(d / "bad.json", m);
    const auto b = test::run(d, "ensemble bad.json -o bad");
    CHECK(b.code == 2);
    CHECK_THAT(b.out, Catch::Contains("mobility_map") && Catch::Contains("vehicle"));
}
