// Parses an SDF world with libsdformat (the reference parser Gazebo uses) and prints its errors;
// exit 0 only if there are none. Model includes resolve from the folder given as the second
// argument (model://NAME -> FOLDER/NAME). Prints the number of models in the first world.
#include <sdf/sdf.hh>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: sdf_check WORLD.sdf [MODEL_FOLDER]\n");
        return 2;
    }
    sdf::ParserConfig config;
    if (argc > 2) config.AddURIPath("model://", argv[2]);
    sdf::Root root;
    const sdf::Errors errors = root.Load(argv[1], config);
    for (const auto& e : errors) std::fprintf(stderr, "sdformat: %s\n", e.Message().c_str());
    if (!errors.empty()) return 1;
    if (root.WorldCount() < 1) {
        std::fprintf(stderr, "sdformat: no world\n");
        return 1;
    }
    std::printf("models %llu\n",
                static_cast<unsigned long long>(root.WorldByIndex(0)->ModelCount()));
    return 0;
}
