// Fuzz target: the user's meshes of `export scene --species-meshes FILE.json`. An input that
// starts with '{' is the JSON file (beside a valid OBJ tree.obj and material library tree.mtl);
// any other input is the OBJ the JSON names (its vertices, faces and mtllib lines, whose paths
// must stay in the OBJ's folder).
#include "fuzz_common.hpp"

#include "ecoterra/export/user_meshes.hpp"

#include <fstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace fs = std::filesystem;
    namespace ex = ecoterra::exporter;
    static const std::vector<ex::SpeciesLook> species = {
        {"Birch", ecoterra::eco::CrownShape::ellipsoid, 20, false, 4},
        {"Pine", ecoterra::eco::CrownShape::cone, 30, true, 3}};
    ecoterra::fuzz::expect_clean([&] {
        const bool json = size > 0 && data[0] == '{';
        const fs::path input = ecoterra::fuzz::as_file(data, size, json ? ".json" : ".obj");
        const fs::path dir = input.parent_path();
        if (json) {
            std::ofstream(dir / "tree.obj", std::ios::trunc)
                << "mtllib tree.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 2\nf 1 2 4\nf 2 3 4\n";
            std::ofstream(dir / "tree.mtl", std::ios::trunc) << "newmtl leaf\nKd 0 1 0\n";
            ex::UserMeshes::load(input, species);
        } else {
            std::ofstream(dir / "meshes.json", std::ios::trunc)
                << R"({"meshes": [{"species": "Pine", "obj": "input.obj", "height_m": 2}]})";
            ex::UserMeshes::load(dir / "meshes.json", species);
        }
    });
    return 0;
}
