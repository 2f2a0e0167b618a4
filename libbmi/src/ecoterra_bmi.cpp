#include "ecoterra/bmi/ecoterra_bmi.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

namespace ecoterra::bmi_impl {

namespace {

constexpr const char* kElevation = "land_surface__elevation";
constexpr const char* kSoilWater = "soil_water__volume_fraction";
constexpr const char* kSurfaceWater = "land_surface_water__depth";
constexpr const char* kRain = "atmosphere_water__precipitation_leq-volume_flux";
constexpr double kSecondsPerDay = 86400.0;

struct VarInfo {
    const char* name;
    const char* units;
    int grid;
    bool input, output;
};

const std::vector<VarInfo>& variables() {
    static const std::vector<VarInfo> v{
        {kElevation, "m", 0, false, true},
        {kSoilWater, "m3 m-3", 0, false, true},
        {kSurfaceWater, "m", 0, false, true},
        // The domain's rain: as output the last day's, as input the next day's (a day's mean).
        {kRain, "m s-1", 1, true, true},
    };
    return v;
}

const VarInfo& info(const std::string& name) {
    for (const auto& v : variables())
        if (name == v.name) return v;
    std::string known;
    for (const auto& v : variables()) known += std::string(known.empty() ? "" : ", ") + v.name;
    throw InputError("BMI: no variable '" + name + "' (ecoterra has " + known + ")");
}

} // namespace

eco::Ecosystem& EcoterraBmi::engine() {
    if (!m_eco) throw Error("BMI: the model is not initialized (call Initialize first)");
    return *m_eco;
}

void EcoterraBmi::Initialize(std::string config_file) {
    nlohmann::json j = parse_json(io::read_text(config_file), config_file);
    apply_overrides(j, m_overrides);
    const auto base = std::filesystem::absolute(config_file).parent_path();
    const eco::EcoScene sc =
        with_context(config_file, [&] { return eco::load_eco_scene(j, base); });
    m_eco = std::make_shared<eco::Ecosystem>(sc);
    m_end_days = static_cast<double>(sc.years) * hydro::kDaysPerYear;
}

void EcoterraBmi::Update() {
    engine().step_day();
}

void EcoterraBmi::UpdateUntil(double time) {
    auto& e = engine();
    if (!std::isfinite(time) || time < e.days_done())
        throw InputError("BMI: UpdateUntil(" + std::to_string(time) + "): the model is at day " +
                         std::to_string(e.days_done()) + " and steps forward only");
    while (e.days_done() < time) e.step_day(); // whole days: to the first day at or after time
}

void EcoterraBmi::Finalize() {
    m_eco.reset();
}

std::string EcoterraBmi::GetComponentName() {
    return "ecoterra";
}

int EcoterraBmi::GetInputItemCount() {
    return static_cast<int>(GetInputVarNames().size());
}
int EcoterraBmi::GetOutputItemCount() {
    return static_cast<int>(GetOutputVarNames().size());
}

std::vector<std::string> EcoterraBmi::GetInputVarNames() {
    std::vector<std::string> n;
    for (const auto& v : variables())
        if (v.input) n.emplace_back(v.name);
    return n;
}

std::vector<std::string> EcoterraBmi::GetOutputVarNames() {
    std::vector<std::string> n;
    for (const auto& v : variables())
        if (v.output) n.emplace_back(v.name);
    return n;
}

int EcoterraBmi::GetVarGrid(std::string name) {
    return info(name).grid;
}
std::string EcoterraBmi::GetVarType(std::string name) {
    info(name);
    return "double";
}
std::string EcoterraBmi::GetVarUnits(std::string name) {
    return info(name).units;
}
int EcoterraBmi::GetVarItemsize(std::string name) {
    info(name);
    return static_cast<int>(sizeof(double));
}
int EcoterraBmi::GetVarNbytes(std::string name) {
    return GetVarItemsize(name) * GetGridSize(info(name).grid);
}
std::string EcoterraBmi::GetVarLocation(std::string name) {
    info(name);
    return "node";
}

double EcoterraBmi::GetCurrentTime() {
    return engine().days_done();
}
double EcoterraBmi::GetStartTime() {
    return 0.0;
}
double EcoterraBmi::GetEndTime() {
    engine();
    return m_end_days;
}
std::string EcoterraBmi::GetTimeUnits() {
    return "d";
}
double EcoterraBmi::GetTimeStep() {
    return 1.0;
}

std::vector<double> EcoterraBmi::values(const std::string& name) {
    info(name);
    auto& e = engine();
    auto raster = [](const RasterD& r) {
        return std::vector<double>(r.data(), r.data() + r.size());
    };
    if (name == kElevation) return raster(e.scene().hydro.dem);
    if (name == kSoilWater) return raster(e.hydrology().soil_moisture());
    if (name == kSurfaceWater) return raster(e.hydrology().surface_water_depth());
    return {e.days_done() > 0 ? e.last_weather().rain_mm / kMmPerM / kSecondsPerDay : 0.0};
}

void EcoterraBmi::GetValue(std::string name, void* dest) {
    const auto v = values(name);
    std::memcpy(dest, v.data(), v.size() * sizeof(double));
}

void* EcoterraBmi::GetValuePtr(std::string name) {
    info(name);
    auto& e = engine();
    if (name == kElevation) return const_cast<double*>(e.scene().hydro.dem.data());
    if (name == kSoilWater) return const_cast<double*>(e.hydrology().soil_moisture().data());
    throw Error("BMI: '" + name + "' is computed on request and has no pointer; use GetValue");
}

void EcoterraBmi::GetValueAtIndices(std::string name, void* dest, int* inds, int count) {
    const auto v = values(name);
    auto* out = static_cast<double*>(dest);
    for (int k = 0; k < count; ++k) {
        if (inds[k] < 0 || static_cast<std::size_t>(inds[k]) >= v.size())
            throw InputError("BMI: index " + std::to_string(inds[k]) + " of '" + name +
                             "' is outside [0, " + std::to_string(v.size()) + ")");
        out[k] = v[static_cast<std::size_t>(inds[k])];
    }
}

void EcoterraBmi::SetValue(std::string name, void* src) {
    if (!info(name).input)
        throw InputError("BMI: '" + name + "' is an output only; ecoterra's inputs are " + kRain);
    const double flux = *static_cast<const double*>(src);
    engine().set_next_rain_mm(flux * kSecondsPerDay * kMmPerM);
}

void EcoterraBmi::SetValueAtIndices(std::string name, int* inds, int count, void* src) {
    for (int k = 0; k < count; ++k)
        if (inds[k] != 0)
            throw InputError("BMI: index " + std::to_string(inds[k]) + " of '" + name +
                             "' is outside [0, 1)");
    if (count > 0) SetValue(name, static_cast<double*>(src) + (count - 1));
}

const GridSpec& EcoterraBmi::grid0() {
    return engine().scene().hydro.dem.grid();
}

void EcoterraBmi::check_grid(int grid) {
    if (grid != 0 && grid != 1)
        throw InputError("BMI: no grid " + std::to_string(grid) +
                         " (ecoterra has grid 0, the terrain, and grid 1, a scalar)");
}

int EcoterraBmi::GetGridRank(const int grid) {
    check_grid(grid);
    return grid == 0 ? 2 : 0;
}
int EcoterraBmi::GetGridSize(const int grid) {
    check_grid(grid);
    return grid == 0 ? static_cast<int>(grid0().size()) : 1;
}
std::string EcoterraBmi::GetGridType(const int grid) {
    check_grid(grid);
    return grid == 0 ? "uniform_rectilinear" : "scalar";
}
void EcoterraBmi::GetGridShape(const int grid, int* shape) {
    check_grid(grid);
    if (grid == 1) return;
    shape[0] = grid0().ny;
    shape[1] = grid0().nx;
}
void EcoterraBmi::GetGridSpacing(const int grid, double* spacing) {
    check_grid(grid);
    if (grid == 1) return;
    spacing[0] = spacing[1] = grid0().cell_size_m;
}
void EcoterraBmi::GetGridOrigin(const int grid, double* origin) {
    check_grid(grid);
    if (grid == 1) return;
    origin[0] = grid0().y_of(0); // the first node: the south-west cell's centre
    origin[1] = grid0().x_of(0);
}
void EcoterraBmi::GetGridX(const int grid, double* x) {
    check_grid(grid);
    if (grid == 1) throw InputError("BMI: grid 1 is a scalar and has no coordinates");
    for (int i = 0; i < grid0().nx; ++i) x[i] = grid0().x_of(i);
}
void EcoterraBmi::GetGridY(const int grid, double* y) {
    check_grid(grid);
    if (grid == 1) throw InputError("BMI: grid 1 is a scalar and has no coordinates");
    for (int j = 0; j < grid0().ny; ++j) y[j] = grid0().y_of(j);
}
void EcoterraBmi::GetGridZ(const int grid, double*) {
    check_grid(grid);
    throw InputError("BMI: ecoterra's grids are two-dimensional; no z coordinate");
}
int EcoterraBmi::GetGridNodeCount(const int grid) {
    return GetGridSize(grid);
}

namespace {
[[noreturn]] void unstructured_only(const char* what) {
    throw InputError(std::string("BMI: ") + what +
                     " belongs to unstructured grids; ecoterra's are uniform rectilinear");
}
} // namespace

int EcoterraBmi::GetGridEdgeCount(const int) {
    unstructured_only("GetGridEdgeCount");
}
int EcoterraBmi::GetGridFaceCount(const int) {
    unstructured_only("GetGridFaceCount");
}
void EcoterraBmi::GetGridEdgeNodes(const int, int*) {
    unstructured_only("GetGridEdgeNodes");
}
void EcoterraBmi::GetGridFaceEdges(const int, int*) {
    unstructured_only("GetGridFaceEdges");
}
void EcoterraBmi::GetGridFaceNodes(const int, int*) {
    unstructured_only("GetGridFaceNodes");
}
void EcoterraBmi::GetGridNodesPerFace(const int, int*) {
    unstructured_only("GetGridNodesPerFace");
}

} // namespace ecoterra::bmi_impl
