// Bad input and interrupted writes, as a user meets them: exit 2 for bad input with the file, key
// and value named, and nothing earlier lost (issue 10 s4).
#include "support/run_cli.hpp"
#include "support/scenes.hpp"

#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>

#include <H5Cpp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace ecoterra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

std::string read(const fs::path& p) {
    return io::read_text(p);
}

/// Cells of a GeoTIFF layer (its width times its height, as GDAL reads it).
long terrain_cells(const fs::path& tif) {
    const RasterD r = terrain::io::read_gdal(tif);
    return static_cast<long>(r.nx()) * r.ny();
}

/// The shared small scene with a snapshot every year.
json tiny_scene(int years, int seed) {
    return test::small_scene(years, "coupled", seed, 1);
}

} // namespace

TEST_CASE("usage errors exit 2", "[cli][bad-input]") {
    test::TempDir dir;
    auto r = test::run(dir, "");
    CHECK(r.code == 2);
    r = test::run(dir, "run --seed abc");
    CHECK(r.code == 2);
    r = test::run(dir, "terrain generate --size 99999999999 -o x.h5");
    CHECK(r.code == 2);
    r = test::run(dir, "--version");
    CHECK(r.code == 0);
}

TEST_CASE("numbers out of range name the file or the key and exit 2", "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "big.json", R"({"terrain": {"generate": {"size": 1e400}}})");
    auto r = test::run(dir, "run big.json -o out.h5");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("big.json"));
    CHECK_THAT(r.out, Catch::Contains("1e400"));
    write(dir / "scene.json", tiny_scene(1, 1).dump());
    r = test::run(dir, "run scene.json -o out.h5 --set simulation.years=1e400");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("simulation.years"));
    CHECK_FALSE(fs::exists(dir / "out.h5"));
}

TEST_CASE("an output that is the input is refused and the input kept", "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(1, 1).dump());
    const std::string scene = read(dir / "s.json");
    auto r = test::run(dir, "run s.json -o s.json --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("destroy the input"));
    CHECK(read(dir / "s.json") == scene);
    r = test::run(dir, "terrain generate --method fbm --D 2.3 --size 32 --cell 1 --seed 1 -o d.h5");
    REQUIRE(r.code == 0);
    const std::string dem = read(dir / "d.h5");
    for (const std::string cmd :
         {"terrain analyze d.h5 --json d.h5", "terrain missions d.h5 --count 2 --length 5 -o d.h5",
          "terrain convert d.h5 ./d.h5", "hydro pond d.h5 --depth-m 0.1 -o d.h5"}) {
        CAPTURE(cmd);
        r = test::run(dir, cmd);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains("d.h5"));
        CHECK(read(dir / "d.h5") == dem);
    }
}

TEST_CASE("non-finite numbers in a DEM or a weather file are refused", "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "inf.asc", "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                           "NODATA_value -9999\n1 2 3\n4 inf 6\n7 8 9\n");
    auto r = test::run(dir, "terrain convert inf.asc out.tif");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("inf.asc"));
    CHECK_THAT(r.out, Catch::Contains("+inf"));
    CHECK_FALSE(fs::exists(dir / "out.tif"));
    write(dir / "w.csv", "date,tmin_c,tmax_c,rain_mm\n2003-01-01,1,10,0\n2003-01-02,1,10,inf\n");
    json sc = tiny_scene(1, 1);
    sc["climate"] = {{"preset", "humid_subtropical"}, {"csv", (dir / "w.csv").string()}};
    write(dir / "s.json", sc.dump());
    r = test::run(dir, "run s.json -o run.h5 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("rain_mm"));
    CHECK_THAT(r.out, Catch::Contains("inf"));
}

TEST_CASE("resume refuses -o", "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(1, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o a.h5 --no-pictures").code == 0);
    auto r = test::run(dir, "run --resume a.h5 -o b.h5 --years 1 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("-o is not used with --resume"));
    CHECK_FALSE(fs::exists(dir / "b.h5"));
    // Also when -o names the default.
    r = test::run(dir, "run --resume a.h5 -o run.h5 --years 1 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("-o is not used with --resume"));
    CHECK_FALSE(fs::exists(dir / "run.h5"));
}

TEST_CASE("a finished run survives a new run to its path that is killed, at any moment",
          "[cli][bad-input][kill][slow]") {
    test::TempDir dir;
    write(dir / "a.json", tiny_scene(3, 1).dump());
    write(dir / "b.json", tiny_scene(40, 2).dump());
    REQUIRE(test::run(dir, "run a.json -o run.h5 --no-pictures").code == 0);
    const auto before = run::read_snapshot_plants(dir / "run.h5", -1);
    const auto info_before = run::read_run_info(dir / "run.h5");
    for (const char* moment : {"0.05", "0.2", "0.4", "0.8", "1.2"}) {
        CAPTURE(moment);
        // The new run in the background, killed with SIGKILL after `moment` seconds.
        const std::string cmd =
            "cd '" + dir.path().string() +
            "' && ('" ECOTERRA_BIN
            "' run b.json -o run.h5 --force --no-pictures > /dev/null 2>&1 & p=$!; "
            "sleep " +
            std::string(moment) + "; kill -9 $p; wait $p) 2>/dev/null; true";
        REQUIRE(std::system(cmd.c_str()) == 0);
        const auto after = run::read_snapshot_plants(dir / "run.h5", -1);
        CHECK(after.year == before.year);
        CHECK(after.values("id") == before.values("id"));
        CHECK(after.values("dbh_m") == before.values("dbh_m"));
        CHECK(run::read_run_info(dir / "run.h5").provenance == info_before.provenance);
    }
    // The killed runs' staging files are swept by the next run into the path (their processes
    // are gone); the run still resumes as before.
    CHECK(test::run(dir, "run --resume run.h5 --years 1 --no-pictures").code == 0);
    for (const auto& e : fs::directory_iterator(dir.path()))
        CHECK(e.path().filename().string().find(".replacing-") == std::string::npos);
    // And it resumes as before.
    CHECK(test::run(dir, "run --resume run.h5 --years 1 --no-pictures").code == 0);
    // A new run that completes replaces it, with snapshots of its own.
    write(dir / "c.json", tiny_scene(2, 3).dump());
    REQUIRE(test::run(dir, "run c.json -o run.h5 --no-pictures").code == 2); // not without --force
    REQUIRE(test::run(dir, "run c.json -o run.h5 --no-pictures --force").code == 0);
    const auto replaced = run::read_snapshot_plants(dir / "run.h5", -1);
    CHECK(replaced.year == 2);
    CHECK(run::read_run_info(dir / "run.h5").snapshots == 2);
    for (const auto& e : fs::directory_iterator(dir.path()))
        CHECK(e.path().filename().string().find(".old-") == std::string::npos);
}

namespace {
/// The names in `dir` that a writer leaves while it works (temporary and staging files).
std::vector<std::string> work_files(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name.find(".tmp-") != std::string::npos ||
            name.find(".replacing-") != std::string::npos)
            out.push_back(name);
    }
    return out;
}

/// Runs `args` in `dir` with files limited to `blocks` of 512 bytes (`ulimit -f`), which fails
/// writes the way a full disk does (EFBIG instead of ENOSPC). Returns the run.
test::Run run_limited(const test::TempDir& dir, const std::string& args, std::uintmax_t blocks) {
    return test::run(dir, args, "ulimit -f " + std::to_string(blocks) + ";");
}
} // namespace

TEST_CASE("a write that fails for want of space is reported, at any size, and loses nothing",
          "[cli][bad-input][disk]") {
    // Writers used to crash when HDF5's final close failed (the close was retried by a destructor)
    // or exit 0 with a dataset silently missing. Every limit from one block to past the file size
    // must either succeed or exit 1 naming the file, with the earlier file intact and no leftovers.
    test::TempDir dir;
    const std::string gen = "terrain generate --method fbm --D 2.3 --size 200 --cell 1 --seed ";
    REQUIRE(test::run(dir, gen + "1 -o d.h5").code == 0);
    REQUIRE(test::run(dir, "hydro pond d.h5 --depth-m 0.05 -o p.h5").code == 0);
    write(dir / "s.json", tiny_scene(3, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o run.h5 --no-pictures").code == 0);
    const auto plants_before = run::read_snapshot_plants(dir / "run.h5", -1);
    const std::string dem = read(dir / "d.h5"), pond = read(dir / "p.h5");
    const std::uintmax_t largest = fs::file_size(dir / "d.h5") / 512 + 2;
    int failures = 0, successes = 0;
    // From 4 KiB: below that LLVM's OpenMP runtime (the sanitizer build) cannot size its
    // registration file in /dev/shm and crashes before main. Every limit below a file's size
    // fails the same way (the file is written in one go at the end).
    for (std::uintmax_t blocks = 8; blocks < 2 * largest; blocks = blocks * 3 / 2 + 1) {
        CAPTURE(blocks);
        for (const std::string what : {"dem", "pond", "run"}) {
            CAPTURE(what);
            const std::string target = what == "dem" ? "d.h5" : what == "pond" ? "p.h5" : "run.h5";
            const auto r =
                what == "dem" ? run_limited(dir, gen + "2 -o d.h5 --force", blocks)
                : what == "pond"
                    ? run_limited(dir, "hydro pond d.h5 --depth-m 0.07 -o p.h5 --force", blocks)
                    : run_limited(dir,
                                  "run s.json -o run.h5 --no-pictures --force "
                                  "--set simulation.seed=2",
                                  blocks);
            CHECK(work_files(dir.path()).empty());
            if (r.code == 0) {
                ++successes;
                continue;
            }
            ++failures;
            CHECK(r.code == 1);
            CHECK_THAT(r.out, Catch::Contains(target));
            CHECK_THAT(r.out, Catch::Contains("File too large"));
            if (what == "dem") CHECK(read(dir / "d.h5") == dem);
            if (what == "pond") CHECK(read(dir / "p.h5") == pond);
            if (what == "run") {
                const auto after = run::read_snapshot_plants(dir / "run.h5", -1);
                CHECK(after.values("id") == plants_before.values("id"));
                CHECK(after.values("dbh_m") == plants_before.values("dbh_m"));
            }
        }
    }
    CHECK(failures > 10);
    CHECK(successes > 0);
    // The surviving run still resumes.
    CHECK(test::run(dir, "run --resume run.h5 --years 1 --no-pictures").code == 0);
}

TEST_CASE("a weather file with a missing day is refused, one with gaps is filled and says so",
          "[cli][bad-input]") {
    test::TempDir dir;
    std::string rows = "date,tmin_c,tmax_c,rain_mm,u2_m_per_s\n";
    for (int d = 1; d <= 31; ++d) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "2003-01-%02d,%d,%d,%s,%s\n", d, 1 + d % 3, 10 + d % 4,
                      d % 7 == 0 ? "" : "1", d < 4 ? "2.5" : "");
        rows += buf;
    }
    for (int m = 2; m <= 12; ++m)
        for (int d = 1; d <= (m == 2 ? 28 : m == 4 || m == 6 || m == 9 || m == 11 ? 30 : 31); ++d) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "2003-%02d-%02d,5,15,1,2.0\n", m, d);
            rows += buf;
        }
    write(dir / "w.csv", rows);
    json sc = tiny_scene(1, 1);
    sc["climate"] = {{"preset", "humid_subtropical"}, {"csv", (dir / "w.csv").string()}};
    write(dir / "s.json", sc.dump());
    auto r = test::run(dir, "run s.json -o run.h5 --no-pictures");
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("w.csv: 4 of 365 days filled: rain_mm: missing, taken as 0"));
    CHECK_THAT(r.out, Catch::Contains("w.csv: 28 of 365 days filled: u2: 2 m/s (FAO-56)"));
    const json prov = run::read_run_info(dir / "run.h5").provenance;
    CHECK(prov.at("observed_weather_filled").at("rain_mm: missing, taken as 0") == 4);
    // 10 March taken out: refused with the file, the line and the missing day.
    const auto cut = rows.find("2003-03-10");
    write(dir / "w.csv", rows.substr(0, cut) + rows.substr(rows.find('\n', cut) + 1));
    r = test::run(dir, "run s.json -o gap.h5 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("w.csv line 70: 2003-03-11 follows 2003-03-09"));
    CHECK_THAT(r.out, Catch::Contains("2003-03-10 is missing"));
    CHECK_FALSE(fs::exists(dir / "gap.h5"));
}

TEST_CASE("resume refuses a run whose snapshots are gone or damaged, and reads one renamed with "
          "its folder",
          "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(3, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o a.h5 --no-pictures").code == 0);
    const auto plants = run::read_snapshot_plants(dir / "a.h5", -1);
    // Renamed together (file and folder): still read and resumed; the resume relinks the file.
    fs::rename(dir / "a.h5", dir / "b.h5");
    fs::rename(dir / "a.snapshots", dir / "b.snapshots");
    CHECK(run::read_snapshot_plants(dir / "b.h5", -1).values("dbh_m") == plants.values("dbh_m"));
    auto r = test::run(dir, "stand b.h5");
    CHECK(r.code == 0);
    fs::copy(dir / "b.h5", dir / "keep.h5");
    fs::copy(dir / "b.snapshots", dir / "keep.snapshots");
    REQUIRE(test::run(dir, "run --resume b.h5 --years 1 --no-pictures").code == 0);
    // Each snapshot deleted, then truncated: refused, naming the run, the snapshot and its file.
    for (int k = 0; k < 3; ++k)
        for (const bool truncate : {false, true}) {
            CAPTURE(k, truncate);
            fs::remove_all(dir / "c.snapshots");
            fs::copy_file(dir / "keep.h5", dir / "c.h5", fs::copy_options::overwrite_existing);
            fs::copy(dir / "keep.snapshots", dir / "c.snapshots");
            const fs::path snap =
                dir / "c.snapshots" / (std::string("000") + char('0' + k) + ".h5");
            if (truncate)
                fs::resize_file(snap, fs::file_size(snap) / 2);
            else
                fs::remove(snap);
            const std::string before = read(dir / "c.h5");
            r = test::run(dir, "run --resume c.h5 --years 1 --no-pictures");
            CHECK(r.code == 2);
            CHECK_THAT(r.out, Catch::Contains("c.h5: snapshot " + std::to_string(k)));
            CHECK_THAT(r.out, Catch::Contains(truncate ? "is damaged" : "is missing"));
            CHECK(read(dir / "c.h5") == before);
        }
    // The whole folder gone.
    fs::remove_all(dir / "c.snapshots");
    r = test::run(dir, "run --resume c.h5 --years 1 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("snapshot 0") && Catch::Contains("renamed together"));
}

TEST_CASE("a picture folder that cannot be made is refused before the run, and loses nothing",
          "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(2, 1).dump());
    write(dir / "blocker", "a file where the picture folder's parent should be");
    auto r = test::run(dir, "run s.json -o fresh.h5 --pictures blocker/pics");
    CHECK(r.code == 1);
    CHECK_THAT(r.out, Catch::Contains("blocker/pics") && Catch::Contains("picture folder"));
    CHECK_THAT(r.out, !Catch::Contains("year 1/2"));
    CHECK_FALSE(fs::exists(dir / "fresh.h5"));
    REQUIRE(test::run(dir, "run s.json -o run.h5 --no-pictures").code == 0);
    const std::string before = read(dir / "run.h5");
    r = test::run(dir,
                  "run s.json -o run.h5 --force --pictures blocker/pics --set simulation.seed=3");
    CHECK(r.code == 1);
    CHECK(read(dir / "run.h5") == before);
    CHECK(work_files(dir.path()).empty());
}

namespace {
/// The state a run file holds: its checkpoint's bytes, then the bytes of every column of its
/// series (the checkpoint keeps only their hashes).
std::vector<std::uint8_t> checkpoint_bytes(const fs::path& run) {
    H5::H5File f(run.string(), H5F_ACC_RDONLY);
    H5::DataSet ds = f.openDataSet("/checkpoint/state");
    std::vector<std::uint8_t> v(static_cast<std::size_t>(ds.getSpace().getSimpleExtentNpoints()));
    ds.read(v.data(), H5::PredType::NATIVE_UINT8);
    for (const char* table : {"/series/daily", "/series/yearly"}) {
        const H5::Group g = f.openGroup(table);
        for (hsize_t k = 0; k < g.getNumObjs(); ++k) {
            const std::string name = g.getObjnameByIdx(k);
            H5::DataSet c = g.openDataSet(name);
            std::vector<double> x(static_cast<std::size_t>(c.getSpace().getSimpleExtentNpoints()));
            c.read(x.data(), H5::PredType::NATIVE_DOUBLE);
            v.insert(v.end(), name.begin(), name.end());
            const auto* b = reinterpret_cast<const std::uint8_t*>(x.data());
            v.insert(v.end(), b, b + x.size() * sizeof(double));
        }
    }
    return v;
}
} // namespace

TEST_CASE("a run killed at any moment and resumed ends bit for bit as one run",
          "[cli][kill][property][slow]") {
    // kill -9 lands anywhere: in a year, in a snapshot write, in the run file's rewrite. Whatever
    // the moment, the run file left behind is whole, and resuming it to the end gives the state
    // of the run that was never killed.
    test::TempDir dir;
    constexpr int kYears = 12;
    write(dir / "s.json", tiny_scene(kYears, 4).dump());
    const auto t0 = std::chrono::steady_clock::now();
    REQUIRE(test::run(dir, "run s.json -o whole.h5 --no-pictures").code == 0);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto whole = checkpoint_bytes(dir / "whole.h5");
    int resumed = 0;
    // Moments spread over the run's own duration (a sanitizer build is several times slower).
    for (int tenth = 1; tenth <= 9; ++tenth) {
        const std::string moment = std::to_string(seconds * tenth / 10.0);
        CAPTURE(moment);
        fs::remove(dir / "k.h5");
        fs::remove_all(dir / "k.snapshots");
        const std::string cmd = "cd '" + dir.path().string() +
                                "' && ('" ECOTERRA_BIN
                                "' run s.json -o k.h5 --no-pictures > /dev/null 2>&1 & p=$!; "
                                "sleep " +
                                moment + "; kill -9 $p; wait $p) 2>/dev/null; true";
        REQUIRE(std::system(cmd.c_str()) == 0);
        if (!fs::exists(dir / "k.h5")) continue; // killed before its first snapshot
        const int done = run::read_run_info(dir / "k.h5").snapshots;
        if (done < kYears) {
            const auto r = test::run(dir, "run --resume k.h5 --years " +
                                              std::to_string(kYears - done) + " --no-pictures");
            REQUIRE(r.code == 0);
            ++resumed;
        }
        CHECK(checkpoint_bytes(dir / "k.h5") == whole);
        CHECK(work_files(dir.path()).empty());
    }
    CHECK(resumed >= 3); // the moments fell inside the run, not all before or after it
}

TEST_CASE("a missing or malformed input file is bad input: exit 2 naming the file",
          "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "header.asc", "ncols 2\nnrows 2.5\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n");
    write(dir / "short.asc", "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n");
    write(dir / "fake.png", "not a png");
    write(dir / "fake.h5", "not hdf5");
    write(dir / "fake.tif", "not a tiff");
    write(dir / "mesh.obj", "v 0 0 0\nv 1 0 0\n");
    // Found by fuzzing: 6 x 6 cells and 65,535 pixel-interleaved bands (GDAL would allocate 17 GB).
    fs::copy_file(test::data_dir() / "../fuzz/crashes/geotiff/huge_block_oom.tif",
                  dir / "bands.tif");
    for (const std::string input : {"header.asc", "short.asc", "fake.png", "fake.h5", "fake.tif",
                                    "mesh.obj", "none.asc", "bands.tif"}) {
        CAPTURE(input);
        const auto r = test::run(dir, "terrain convert " + input + " out.tif");
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains(input));
        CHECK_FALSE(fs::exists(dir / "out.tif"));
    }
}

TEST_CASE("one rule for existing outputs: refused without --force, replaced with it and said so",
          "[cli][bad-input][outputs][slow]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(2, 1).dump());
    json hs = tiny_scene(1, 1);
    hs.erase("vegetation");
    hs["simulation"].erase("snapshot_interval_years");
    write(dir / "h.json", hs.dump());
    const std::string vehicle = (test::data_dir() / "vehicles/mrzr4.json").string();
    REQUIRE(
        test::run(dir, "terrain generate --method fbm --size 48 --cell 1 --seed 1 -o d.asc").code ==
        0);
    REQUIRE(test::run(dir, "run s.json -o r.h5 --no-pictures").code == 0);
    // Every command that writes, with the output it is pointed at (each created by the first
    // pass, refused by the second, replaced by the third).
    struct Case {
        std::string args, output;
    };
    const std::vector<Case> cases = {
        {"terrain generate --method fbm --size 48 --cell 1 --seed 2 -o g.tif", "g.tif"},
        {"terrain analyze d.asc --json a.json", "a.json"},
        {"terrain analyze d.asc --png pics", "pics"},
        {"terrain missions d.asc --count 3 --length 10 -o m.csv", "m.csv"},
        {"terrain convert d.asc c.png", "c.png"},
        {"hydro pond d.asc --depth-m 0.05 -o p.h5", "p.h5"},
        {"hydro run h.json -o hr.h5", "hr.h5"},
        {"run s.json -o r2.h5 --no-pictures", "r2.h5"},
        {"run s.json -o r3.h5 --years 1", "r3.h5"},
        {"stand r.h5 --json st.json", "st.json"},
        {"export vegetation r.h5 -o v.csv", "v.csv"},
        {"export deadwood r.h5 -o dw.csv", "dw.csv"},
        {"export scene r.h5 --format gltf -o sc.glb --no-pictures", "sc.glb"},
        {"export scene r.h5 --format mavs -o mavs --no-pictures", "mavs"},
        {"export layers r.h5 -o layers", "layers"},
        {"mobility r.h5 --vehicle " + vehicle +
             " --lines 5 --length 20 --json mob.json --no-pictures",
         "mob.json"},
        {"terrain traverse d.asc --vehicle " + vehicle + " --count 2 --json tr.json", "tr.json"},
        {"terrain traverse d.asc --vehicle " + vehicle + " --count 2 --pictures trp", "trp"},
    };
    auto snapshot_of = [&](const std::string& out) {
        const fs::path p = dir / out;
        if (!fs::is_directory(p)) return read(p);
        std::string all;
        for (const auto& e : fs::recursive_directory_iterator(p))
            if (e.is_regular_file()) all += e.path().string() + "\n" + read(e.path());
        return all;
    };
    for (const auto& c : cases) {
        CAPTURE(c.args);
        auto r = test::run(dir, c.args);
        INFO(r.out);
        REQUIRE(r.code == 0);
        const std::string before = snapshot_of(c.output);
        r = test::run(dir, c.args);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains(c.output) && Catch::Contains("give --force"));
        CHECK(snapshot_of(c.output) == before);
        r = test::run(dir, c.args + " --force");
        CHECK(r.code == 0);
        CHECK_THAT(r.out, Catch::Contains("is replaced (--force)"));
    }
    for (const auto& e : fs::directory_iterator(dir.path()))
        CHECK(e.path().filename().string().find(".partial-") == std::string::npos);
    // A run's picture folder is an output of its own.
    fs::remove(dir / "r3.h5");
    auto r = test::run(dir, "run s.json -o r3.h5 --years 1");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--pictures r3.pictures: the folder exists with files"));
    CHECK_FALSE(fs::exists(dir / "r3.h5"));
}

TEST_CASE("terrain convert never destroys its input or a run", "[cli][bad-input][outputs]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(2, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o base.h5 --no-pictures").code == 0);
    fs::copy_file(dir / "base.h5", dir / "cv.h5");
    const std::string run_bytes = read(dir / "cv.h5");
    const std::string snap_bytes = read(dir / "base.snapshots/0001.h5");
    // Output = input through a dataset reference: refused, even with --force.
    for (const std::string force : {"", " --force"}) {
        auto r = test::run(dir, "terrain convert cv.h5:/terrain/elevation cv.h5" + force);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains("the output is the input cv.h5"));
        // Another run file and a snapshot file: refused, even with --force.
        r = test::run(dir, "terrain convert base.h5:/terrain/elevation cv.h5" + force);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains("cv.h5: is an ecoterra run file"));
        r = test::run(dir, "terrain convert cv.h5 base.snapshots/0001.h5" + force);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains("is an ecoterra snapshot file"));
        r = test::run(dir, "terrain generate --method fbm --size 32 -o cv.h5" + force);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains("cv.h5: is an ecoterra run file"));
    }
    CHECK(read(dir / "cv.h5") == run_bytes);
    CHECK(read(dir / "base.snapshots/0001.h5") == snap_bytes);
    CHECK(run::read_run_info(dir / "cv.h5").snapshots == 2);
    // A plain raster file is another matter: refused without --force, replaced with it.
    REQUIRE(test::run(dir, "terrain convert cv.h5 t.tif").code == 0);
    CHECK(test::run(dir, "terrain convert cv.h5 t.tif").code == 2);
    CHECK(test::run(dir, "terrain convert cv.h5 t.tif --force").code == 0);
}

namespace {
/// Starts `args` in the background in `dir`; returns its pid once the run holds its lock.
long start_locked_run(const test::TempDir& dir, const std::string& args, const fs::path& lock) {
    const std::string cmd = "cd '" + dir.path().string() + "' && ('" ECOTERRA_BIN "' " + args +
                            " > bg.log 2>&1 & echo $! > bg.pid)";
    REQUIRE(std::system(cmd.c_str()) == 0);
    for (int i = 0; i < 600 && !fs::exists(lock); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(fs::exists(lock));
    return std::stol(read(dir / "bg.pid"));
}
void wait_for(long pid) {
    for (int i = 0; i < 6000 && ::kill(static_cast<pid_t>(pid), 0) == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
}
} // namespace

TEST_CASE("two processes never write one run: a second run or resume is refused while the first "
          "works",
          "[cli][bad-input][lock][slow]") {
    test::TempDir dir;
    write(dir / "long.json", tiny_scene(60, 1).dump());
    write(dir / "other.json", tiny_scene(3, 2).dump());
    const fs::path lock = dir / ".run.h5.lock";
    // A new run to the same -o while the first runs: refused, naming the other process.
    long pid = start_locked_run(dir, "run long.json -o run.h5 --no-pictures", lock);
    auto r = test::run(dir, "run other.json -o run.h5 --no-pictures --force");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("run.h5: another ecoterra process (pid " +
                                      std::to_string(pid) + ") is writing it now"));
    wait_for(pid);
    CHECK_THAT(read(dir / "bg.log"), Catch::Contains("wrote run.h5"));
    CHECK_FALSE(fs::exists(lock)); // released and removed
    // Every snapshot is the first run's (they once mixed: 0000 from one seed, the rest from the
    // other).
    const auto info = run::read_run_info(dir / "run.h5");
    CHECK(info.provenance["scene"]["simulation"]["seed"] == 1);
    CHECK(run::read_snapshot_plants(dir / "run.h5", 0).year == 1);
    CHECK(run::read_snapshot_plants(dir / "run.h5", -1).year == 60);
    // Two resumes at once: the second is refused; the first's report stands.
    pid = start_locked_run(dir, "run --resume run.h5 --years 40 --no-pictures", lock);
    r = test::run(dir, "run --resume run.h5 --years 1 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("is writing it now"));
    wait_for(pid);
    CHECK(run::read_snapshot_plants(dir / "run.h5", -1).year == 100);
    // A holder killed with SIGKILL leaves no lock behind that stops the next run.
    pid = start_locked_run(dir, "run long.json -o run.h5 --no-pictures --force", lock);
    ::kill(static_cast<pid_t>(pid), SIGKILL);
    wait_for(pid);
    r = test::run(dir, "run other.json -o run.h5 --no-pictures --force");
    INFO(r.out);
    CHECK(r.code == 0);
    CHECK(run::read_run_info(dir / "run.h5").provenance["scene"]["simulation"]["seed"] == 2);
    CHECK_FALSE(fs::exists(lock));
}

TEST_CASE("snapshots are checksummed: a byte changed anywhere in one is refused on resume and read",
          "[cli][bad-input][checksum]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(3, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o a.h5 --no-pictures").code == 0);
    fs::copy(dir / "a.snapshots", dir / "keep.snapshots");
    const std::string run_before = read(dir / "a.h5");
    // Each snapshot, bytes flipped at spread positions (inside compressed chunks, in the HDF5
    // metadata, near the end): every one is caught, by resume and by every reader.
    int cases = 0;
    for (int k = 0; k < 3; ++k) {
        const fs::path snap = dir / "a.snapshots" / (std::string("000") + char('0' + k) + ".h5");
        const std::string good = read(dir / "keep.snapshots" / snap.filename());
        for (int at = 1; at < 20; at += 3) {
            CAPTURE(k, at);
            std::string bad = good;
            const std::size_t pos = bad.size() * static_cast<std::size_t>(at) / 20;
            bad[pos] = static_cast<char>(bad[pos] ^ 0x5a);
            write(snap, bad);
            const std::string expect = "a.h5: snapshot " + std::to_string(k);
            auto r = test::run(dir, "run --resume a.h5 --years 1 --no-pictures");
            CHECK(r.code == 2);
            CHECK_THAT(r.out, Catch::Contains(expect) && Catch::Contains("is damaged"));
            r = test::run(dir, "stand a.h5 --snapshot " + std::to_string(k));
            CHECK(r.code == 2);
            CHECK_THAT(r.out, Catch::Contains(expect) && Catch::Contains("checksum"));
            r = test::run(dir, "export layers a.h5 -o layers --snapshot " + std::to_string(k));
            CHECK(r.code == 2);
            CHECK_THAT(r.out, Catch::Contains(expect));
            CHECK_FALSE(fs::exists(dir / "layers"));
            CHECK(read(dir / "a.h5") == run_before);
            ++cases;
        }
        write(snap, good);
    }
    CHECK(cases == 21);
    // Whole again: read and resumed.
    CHECK(test::run(dir, "stand a.h5 --snapshot 1").code == 0);
    auto r = test::run(dir, "run --resume a.h5 --years 1 --no-pictures");
    INFO(r.out);
    CHECK(r.code == 0);
    // A run written before snapshots had checksums still reads and resumes.
    {
        H5::H5File f((dir / "a.h5").string(), H5F_ACC_RDWR);
        f.openGroup("/snapshots").removeAttr("checksums_fnv1a64");
    }
    CHECK(test::run(dir, "stand a.h5 --snapshot 0").code == 0);
    CHECK(test::run(dir, "run --resume a.h5 --years 1 --no-pictures").code == 0);
}

TEST_CASE("resume: a run file's series changed or missing are refused, naming the column",
          "[cli][bad-input][checksum]") {
    // The run file's checkpoint keeps its series' hashes, their values are in /series.
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(2, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o a.h5 --no-pictures").code == 0);
    std::vector<double> rain;
    const auto rewrite_rain = [&](double add) {
        H5::H5File f((dir / "a.h5").string(), H5F_ACC_RDWR);
        H5::DataSet ds = f.openDataSet("/series/daily/rain_mm");
        rain.resize(static_cast<std::size_t>(ds.getSpace().getSimpleExtentNpoints()));
        if (add != 0) ds.read(rain.data(), H5::PredType::NATIVE_DOUBLE);
        std::vector<double> v = rain;
        v[v.size() / 2] += add;
        ds.write(v.data(), H5::PredType::NATIVE_DOUBLE);
    };
    rewrite_rain(1.0);
    std::string before = read(dir / "a.h5");
    auto r = test::run(dir, "run --resume a.h5 --years 1 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("a.h5") && Catch::Contains("/series/daily/rain_mm") &&
                          Catch::Contains("damaged"));
    CHECK(read(dir / "a.h5") == before);
    rewrite_rain(0.0); // the values it had
    {
        H5::H5File f((dir / "a.h5").string(), H5F_ACC_RDWR);
        f.unlink("/series/yearly/rain_mm");
    }
    before = read(dir / "a.h5");
    r = test::run(dir, "run --resume a.h5 --years 1 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("a.h5: cannot read /series/yearly/rain_mm"));
    CHECK(read(dir / "a.h5") == before);
}

TEST_CASE("HDF5 inputs that are not rasters, damaged files and huge numbers get clear errors",
          "[cli][bad-input]") {
    test::TempDir dir;
    {
        // A group, a dataset of complex numbers (a compound of two floats) and one of strings.
        H5::H5File f((dir / "odd.h5").string(), H5F_ACC_TRUNC);
        f.createGroup("/g");
        H5::CompType complex(2 * sizeof(float));
        complex.insertMember("r", 0, H5::PredType::NATIVE_FLOAT);
        complex.insertMember("i", sizeof(float), H5::PredType::NATIVE_FLOAT);
        const hsize_t dims[2] = {4, 4};
        f.createDataSet("/z", complex, H5::DataSpace(2, dims));
        f.createDataSet("/s", H5::StrType(H5::PredType::C_S1, 8), H5::DataSpace(2, dims));
    }
    write(dir / "s.json", tiny_scene(1, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o run.h5 --no-pictures").code == 0);
    const std::string bytes = read(dir / "run.h5");
    write(dir / "cut.h5", bytes.substr(0, bytes.size() / 3));
    write(dir / "stems.csv", "x_m,y_m,dbh_cm\n1,2,3\n");
    struct Case {
        std::string args, says;
    };
    const Case cases[] = {
        {"terrain analyze odd.h5:/g", "odd.h5: /g is a group, not a raster dataset"},
        {"terrain analyze odd.h5:/z", "dataset /z holds compound records"},
        {"terrain convert odd.h5:/s s.tif", "dataset /s holds strings, not numbers"},
        {"terrain analyze cut.h5", "cut.h5: cannot read /elevation: the file is damaged or "
                                   "truncated"},
        {"terrain convert cut.h5:/terrain/elevation t.tif", "the file is damaged or truncated"},
        {"stand cut.h5", "cut.h5: the HDF5 file is damaged or truncated"},
        {"stand stems.csv", "stems.csv: not an HDF5 file; give an ecoterra run file"},
        {"run s.json -o x.h5 --set simulation.years=1e308",
         "simulation.years = 1e+308 is outside [1, 10000]"},
        {"run s.json -o x.h5 --set simulation.seed=1e300", "simulation.seed = 1e+300"},
    };
    for (const auto& c : cases) {
        const auto r = test::run(dir, c.args);
        INFO(c.args + "\n" + r.out);
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains(c.says));
    }
    // A region far past the terrain on every side covers the whole terrain.
    auto r = test::run(dir, "export layers run.h5 -o all --region -1e308,-1e308,1e308,1e308");
    INFO(r.out);
    CHECK(r.code == 0);
    CHECK(terrain_cells(dir / "all/elevation_m.tif") == 400);
    r = test::run(dir, "export layers run.h5 -o part --region 0,0,1e308,1e308");
    CHECK(r.code == 0);
}

TEST_CASE("damaged plant values, ambiguous CSV headers and killed exports' staging folders",
          "[cli][bad-input]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(2, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o run.h5 --no-pictures").code == 0);
    fs::copy(dir / "run.snapshots", dir / "keep.snapshots");
    // A snapshot whose values were edited: the checksum refuses it; with no checksum (a run of an
    // older ecoterra) the values themselves are checked.
    struct Edit {
        std::string column;
        double value;
        std::string says;
    };
    const Edit edits[] = {{"dbh_m", std::nan(""), "dbh_m = nan is not a size"},
                          {"dbh_m", -0.2, "dbh_m = -0.2 is not a size"},
                          {"height_m", -1, "height_m = -1 is not a size"},
                          {"crown_radius_m", INFINITY, "crown_radius_m = inf is not a size"},
                          {"x_m", std::nan(""), "x_m = nan is not a finite number"}};
    for (const bool checksums : {true, false})
        for (const auto& e : edits) {
            CAPTURE(checksums, e.column, e.value);
            fs::remove_all(dir / "run.snapshots");
            fs::copy(dir / "keep.snapshots", dir / "run.snapshots");
            {
                H5::H5File f((dir / "run.snapshots/0000.h5").string(), H5F_ACC_RDWR);
                H5::DataSet ds = f.openDataSet("/0000/plants/" + e.column);
                std::vector<double> v(
                    static_cast<std::size_t>(ds.getSpace().getSimpleExtentNpoints()));
                ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
                REQUIRE(v.size() > 3);
                v[3] = e.value;
                ds.write(v.data(), H5::PredType::NATIVE_DOUBLE);
            }
            if (!checksums) {
                H5::H5File f((dir / "run.h5").string(), H5F_ACC_RDWR);
                H5::Group g = f.openGroup("/snapshots");
                if (g.attrExists("checksums_fnv1a64")) g.removeAttr("checksums_fnv1a64");
            }
            for (const std::string cmd :
                 {"stand run.h5 --snapshot 0", "export vegetation run.h5 --snapshot 0 -o v.csv"}) {
                const auto r = test::run(dir, cmd);
                INFO(cmd + "\n" + r.out);
                CHECK(r.code == 2);
                CHECK_THAT(r.out, Catch::Contains("run.h5: snapshot 0"));
                CHECK_THAT(r.out, Catch::Contains(checksums ? "checksum" : e.says));
            }
            CHECK_FALSE(fs::exists(dir / "v.csv"));
        }
    // A stem list naming a column twice is ambiguous: refused, naming the column.
    write(dir / "dup.csv", "x_m,y_m,dbh_cm,dbh_cm\n5,5,10,20\n");
    REQUIRE(test::run(dir, "terrain generate --method fbm --size 40 --cell 1 -o d.asc").code == 0);
    auto r = test::run(dir, "mobility --stems dup.csv --dem d.asc --vehicle " +
                                (test::data_dir() / "vehicles/mrzr4.json").string());
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("dup.csv: the header names column dbh_cm twice (columns 3 "
                                      "and 4)"));
    // Staging folders of killed exports (a process of this host that is gone) are removed by the
    // next export into the same place; a live process's and another host's are left alone.
    fs::remove_all(dir / "run.snapshots");
    fs::copy(dir / "keep.snapshots", dir / "run.snapshots");
    const long gone = [] {
        const pid_t p = ::fork();
        if (p == 0) ::_exit(0);
        ::waitpid(p, nullptr, 0);
        return static_cast<long>(p);
    }();
    char host[256] = {0};
    ::gethostname(host, sizeof host - 1);
    const std::string me = std::string(host) + "-";
    for (const std::string& name : {".layers.partial-" + me + std::to_string(gone),
                                    ".layers.partial-" + me + std::to_string(::getpid()),
                                    ".layers.partial-elsewhere-" + std::to_string(gone)}) {
        fs::create_directories(dir / name);
        write(dir / name / "elevation_m.tif", std::string(1000, 'x'));
    }
    r = test::run(dir, "export layers run.h5 -o layers");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_FALSE(fs::exists(dir / (".layers.partial-" + me + std::to_string(gone))));
    CHECK(fs::exists(dir / (".layers.partial-" + me + std::to_string(::getpid()))));
    CHECK(fs::exists(dir / (".layers.partial-elsewhere-" + std::to_string(gone))));
}

TEST_CASE("a scene larger than the memory available is refused at the start, naming its size",
          "[cli][bad-input][memory]") {
    test::TempDir dir;
    write(dir / "s.json", tiny_scene(1, 1).dump());
    REQUIRE(test::run(dir, "run s.json -o run.h5 --no-pictures").code == 0);
    const std::string before = read(dir / "run.h5");
    // The same scene fits in 1 GiB; in 10 MB it does not, and the earlier run stays as it was.
    auto r = test::run(dir, "run s.json -o run.h5 --force --no-pictures",
                       "ECOTERRA_MEMORY_LIMIT_GIB=0.01");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("needs an estimated") && Catch::Contains("terrain cells") &&
                          Catch::Contains("plants x 2000 B") &&
                          Catch::Contains("0.01 GiB is available (ECOTERRA_MEMORY_LIMIT_GIB)"));
    CHECK(read(dir / "run.h5") == before);
    CHECK(
        test::run(dir, "run s.json -o run2.h5 --no-pictures", "ECOTERRA_MEMORY_LIMIT_GIB=1").code ==
        0);
    std::ifstream hf(test::data_dir() / "scenes/hydro_quickstart.json");
    json hydro = json::parse(hf);
    hydro["terrain"]["generate"]["size"] = 16;
    write(dir / "h.json", hydro.dump());
    r = test::run(dir, "hydro run h.json -o h.h5", "ECOTERRA_MEMORY_LIMIT_GIB=0.01");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("needs an estimated") && !Catch::Contains("plants"));
    CHECK(!std::filesystem::exists(dir / "h.h5"));
    r = test::run(dir, "run s.json -o run3.h5", "ECOTERRA_MEMORY_LIMIT_GIB=lots");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("ECOTERRA_MEMORY_LIMIT_GIB = 'lots'"));
}
