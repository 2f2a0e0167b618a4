// libcore's shared helpers: the one hash (FNV-1a 64, against the reference vectors of its
// authors), the one dotted-key setter and --set parser, the provenance record, checkpoint
// sections and the CSV reader's numbers.
#include "support/temp_dir.hpp"

#include "ecoterra/archive.hpp"
#include "ecoterra/csv.hpp"
#include "ecoterra/hash.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/io/staging.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/provenance.hpp"

#include <catch2/catch.hpp>

#include <fstream>

using namespace ecoterra;
using nlohmann::json;
namespace fs = std::filesystem;

TEST_CASE("hash: FNV-1a 64 gives the published test vectors", "[core][hash]") {
    // Fowler, Noll & Vo's reference values (draft-eastlake-fnv, test suite of fnv-5.0.3).
    CHECK(fnv1a64_text("") == 0xcbf29ce484222325ULL);
    CHECK(fnv1a64_text("a") == 0xaf63dc4c8601ec8cULL);
    CHECK(fnv1a64_text("foobar") == 0x85944171f73967e8ULL);
    static_assert(fnv1a64_text("a") == 0xaf63dc4c8601ec8cULL, "usable at compile time");
    // Bytes, text and a file of the same bytes agree, and a hash continues over pieces.
    const std::string s = "ecoterra grows synthetic off-road worlds";
    CHECK(fnv1a64(s.data(), s.size()) == fnv1a64_text(s));
    CHECK(fnv1a64_text(s.substr(10), fnv1a64_text(s.substr(0, 10))) == fnv1a64_text(s));
    test::TempDir dir;
    std::ofstream(dir / "f.bin", std::ios::binary) << s;
    CHECK(fnv1a64_file(dir / "f.bin") == fnv1a64_text(s));
    CHECK_THROWS_WITH(fnv1a64_file(dir / "missing.bin"),
                      Catch::Contains("missing.bin") && Catch::Contains("cannot read"));
}

TEST_CASE("dotted keys: one setter for --set and ensemble overrides", "[core][json]") {
    json j = {{"vegetation", {{"initial", "bare"}, {"competition", "coupled"}}}};
    set_dotted(j, "vegetation.initial.random.stems_per_ha", 800);
    CHECK(j["vegetation"]["initial"] == json{{"random", {{"stems_per_ha", 800}}}});
    CHECK(j["vegetation"]["competition"] == "coupled");
    set_dotted(j, "simulation.years", 3);
    CHECK(j["simulation"]["years"] == 3);
    apply_overrides(j, {"climate.preset=temperate", "simulation.seed=7", "a.b=[1,2]",
                        "vegetation.initial={\"file\":\"s.csv\"}"});
    CHECK(j["climate"]["preset"] == "temperate"); // not JSON: a string
    CHECK(j["simulation"]["seed"] == 7);
    CHECK(j["a"]["b"] == json::array({1, 2}));
    CHECK(j["vegetation"]["initial"]["file"] == "s.csv");
    CHECK_THROWS_WITH(apply_overrides(j, {"simulation.years"}),
                      Catch::Contains("KEY=VALUE") && Catch::Contains("simulation.years"));
    CHECK_THROWS_WITH(apply_overrides(j, {"=3"}), Catch::Contains("KEY=VALUE"));
    CHECK_THROWS_WITH(apply_overrides(j, {"x=1e999"}), Catch::Contains("out of range"));
}

TEST_CASE("provenance: one record of software and version, the command line for commands",
          "[core][provenance]") {
    const json p = provenance({{"member", 3}});
    CHECK(p["software"] == "ecoterra");
    CHECK(p["version"] == std::string(version()));
    CHECK(p["member"] == 3);
    CHECK_FALSE(p.contains("command_line"));
    char a0[] = "ecoterra", a1[] = "stand", a2[] = "run.h5";
    char* argv[] = {a0, a1, a2};
    set_command_line(3, argv);
    CHECK(command_provenance()["command_line"] == "ecoterra stand run.h5");
    CHECK(command_provenance({{"version", "x"}})["version"] == "x"); // extra entries win
}

TEST_CASE("checkpoint sections: read by name and version, unknown and doubled ones refused",
          "[core][checkpoint]") {
    ArchiveWriter a;
    SectionWriter w(a);
    w.section("one", 2, [](ArchiveWriter& s) { s.put(1.5); });
    w.section("two", 1, [](ArchiveWriter& s) { s.put_string("x"); });
    {
        ArchiveReader in(a.bytes().data(), a.bytes().size(), "cp");
        SectionReader r(in, "cp");
        CHECK(r.version("one") == 2);
        CHECK(r.version("three") == 0);
        double v = 0;
        // An older version the reader converts is accepted; the body sees which it was.
        r.read("one", 1, 2, [&](ArchiveReader& s, std::uint32_t version) {
            CHECK(version == 2);
            v = s.get<double>();
        });
        CHECK(v == 1.5);
        CHECK_THROWS_WITH(r.finish(), Catch::Contains("'two'") && Catch::Contains("newer"));
        CHECK_THROWS_WITH(r.read("two", 2, 3, [](ArchiveReader&, std::uint32_t) {}),
                          Catch::Contains("'two' has version 1") &&
                              Catch::Contains("versions 2 to 3"));
        CHECK_THROWS_WITH(r.read("two", 1, 1, [](ArchiveReader&, std::uint32_t) {}),
                          Catch::Contains("'two' holds more"));
    }
    w.section("one", 1, [](ArchiveWriter& s) { s.put(2.5); });
    ArchiveReader in(a.bytes().data(), a.bytes().size(), "cp");
    CHECK_THROWS_WITH(SectionReader(in, "cp"), Catch::Contains("section 'one' twice"));
}

TEST_CASE("csv: numbers in full, spaces allowed, the column and line named otherwise",
          "[core][csv]") {
    test::TempDir dir;
    std::ofstream(dir / "t.csv") << "a,b\n 1.5 ,2\n12abc,3\n,4\ninf,5\n";
    CsvReader csv(dir / "t.csv", "test table");
    const int a = csv.require("a");
    REQUIRE(csv.next());
    CHECK(csv.number(a, "a") == 1.5);
    CHECK(csv.fields() == 2);
    for (const char* bad : {"'12abc'", "''", "'inf'"}) {
        REQUIRE(csv.next());
        CHECK_THROWS_WITH(csv.number(a, "a"),
                          Catch::Contains("a = " + std::string(bad) + " is not a finite number") &&
                              Catch::Contains("t.csv line"));
    }
    CHECK_THROWS_WITH(csv.require("c"), Catch::Contains("lacks column c"));
}

TEST_CASE("csv: quoted fields (RFC 4180) round-trip through csv_field and the reader",
          "[core][csv]") {
    test::TempDir dir;
    // Fields with commas, quotes, spaces and nothing, each with a number beside it; pandas and
    // spreadsheet programs write quotes this way too.
    const std::vector<std::string> texts{
        "Oak", "Oak, white", "say \"hi\"", "", " spaced ", "a,\"b\",c", "\"", ",", "Birch (paper)"};
    std::string file = "name,value\n";
    for (std::size_t k = 0; k < texts.size(); ++k)
        file += csv_field(texts[k]) + "," + std::to_string(k) + "\n";
    std::ofstream(dir / "q.csv") << file;
    CHECK(csv_field("Oak, white") == "\"Oak, white\"");
    CHECK(csv_field("say \"hi\"") == "\"say \"\"hi\"\"\"");
    CHECK(csv_field("plain") == "plain");
    CsvReader csv(dir / "q.csv", "test table");
    const int name = csv.require("name"), value = csv.require("value");
    std::size_t k = 0;
    while (csv.next()) {
        CAPTURE(k);
        REQUIRE(k < texts.size());
        CHECK(csv.fields() == 2);
        CHECK(csv.text(name) == texts[k]);
        CHECK(csv.number(value, "value") == static_cast<double>(k));
        ++k;
    }
    // The empty text's row reads as a row (its one field empty, then the value), not a blank.
    CHECK(k == texts.size());
}

TEST_CASE("staging: names carry host and process, a folder is replaced whole", "[core][staging]") {
    test::TempDir dir;
    const fs::path p = io::staging_path(dir.path(), "run", "replacing", ".h5");
    CHECK(p.filename().string() == ".run.replacing-" + io::process_tag() + ".h5");
    // A new folder moves into place; an existing one is replaced, nothing of it left aside.
    const fs::path target = dir / "members";
    for (const std::string content : {"first", "second"}) {
        const fs::path stage = io::staging_path(dir.path(), "members", "partial");
        fs::create_directories(stage);
        std::ofstream(stage / "f.txt") << content;
        io::replace_folder(stage, target);
        CHECK(io::read_text(target / "f.txt") == content);
        CHECK_FALSE(fs::exists(stage));
    }
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(dir.path())) entries += e.path() != target;
    CHECK(entries == 0);
    // This live process's staging is not swept.
    fs::create_directories(io::staging_path(dir.path(), "x", "partial"));
    CHECK(io::sweep_dead_staging(dir.path(), "x", ".partial-") == 0);
}
