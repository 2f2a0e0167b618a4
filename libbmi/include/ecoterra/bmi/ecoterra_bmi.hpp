#pragma once
// ecoterra's coupled run behind the CSDMS Basic Model Interface 2.0 (docs/python.md, "BMI"): one
// update is one day; the configuration file is a scene file (docs/scenes.md). Variables carry
// CSDMS standard names; grid 0 is the terrain's uniform rectilinear grid (values at the cell
// centres, shape [ny, nx], row 0 at the south edge), grid 1 a scalar for the domain's rain.
#include "ecoterra/bmi/bmi.hpp"
#include "ecoterra/eco/ecosystem.hpp"

#include <memory>

namespace ecoterra::bmi_impl {

class EcoterraBmi : public bmi::Bmi {
public:
    EcoterraBmi() = default;
    /// With overrides applied to the scene at Initialize, as `ecoterra run --set KEY=VALUE`.
    explicit EcoterraBmi(std::vector<std::string> overrides) : m_overrides(std::move(overrides)) {}

    void Initialize(std::string config_file) override;
    void Update() override;
    void UpdateUntil(double time) override;
    void Finalize() override;

    std::string GetComponentName() override;
    int GetInputItemCount() override;
    int GetOutputItemCount() override;
    std::vector<std::string> GetInputVarNames() override;
    std::vector<std::string> GetOutputVarNames() override;

    int GetVarGrid(std::string name) override;
    std::string GetVarType(std::string name) override;
    std::string GetVarUnits(std::string name) override;
    int GetVarItemsize(std::string name) override;
    int GetVarNbytes(std::string name) override;
    std::string GetVarLocation(std::string name) override;

    double GetCurrentTime() override;
    double GetStartTime() override;
    double GetEndTime() override;
    std::string GetTimeUnits() override;
    double GetTimeStep() override;

    void GetValue(std::string name, void* dest) override;
    /// The engine's own memory for land_surface__elevation and soil_water__volume_fraction (read
    /// it, do not write it: the water budget would break); Error for the others.
    void* GetValuePtr(std::string name) override;
    void GetValueAtIndices(std::string name, void* dest, int* inds, int count) override;
    void SetValue(std::string name, void* src) override;
    void SetValueAtIndices(std::string name, int* inds, int count, void* src) override;

    int GetGridRank(const int grid) override;
    int GetGridSize(const int grid) override;
    std::string GetGridType(const int grid) override;
    void GetGridShape(const int grid, int* shape) override;
    void GetGridSpacing(const int grid, double* spacing) override;
    void GetGridOrigin(const int grid, double* origin) override;
    void GetGridX(const int grid, double* x) override;
    void GetGridY(const int grid, double* y) override;
    void GetGridZ(const int grid, double* z) override;
    int GetGridNodeCount(const int grid) override;
    int GetGridEdgeCount(const int grid) override;
    int GetGridFaceCount(const int grid) override;
    void GetGridEdgeNodes(const int grid, int* edge_nodes) override;
    void GetGridFaceEdges(const int grid, int* face_edges) override;
    void GetGridFaceNodes(const int grid, int* face_nodes) override;
    void GetGridNodesPerFace(const int grid, int* nodes_per_face) override;

    /// The engine (Error before Initialize or after Finalize).
    eco::Ecosystem& engine();
    /// The engine, shared: a holder of GetValuePtr's memory keeps it alive past Finalize.
    std::shared_ptr<eco::Ecosystem> shared_engine() {
        engine();
        return m_eco;
    }

private:
    /// The values of `name` as doubles (every variable is float64).
    std::vector<double> values(const std::string& name);
    const GridSpec& grid0();
    void check_grid(int grid);

    std::vector<std::string> m_overrides;
    std::shared_ptr<eco::Ecosystem> m_eco; ///< shared with views that outlive Finalize
    double m_end_days = 0;
};

} // namespace ecoterra::bmi_impl
