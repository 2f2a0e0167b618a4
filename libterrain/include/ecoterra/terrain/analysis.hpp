#pragma once
// The full terrain analysis behind `ecoterra terrain analyze`: RMS roughness, gradient classes
// (raw and closed), radial PSD and fractal dimension, slope statistics; as JSON and text.
#include "ecoterra/terrain/fractal_dimension.hpp"
#include "ecoterra/terrain/missions.hpp"
#include "ecoterra/terrain/roughness.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace ecoterra::terrain {

struct AnalysisOptions {
    RmsOptions rms;
    ClassThresholds thresholds;
    double border_m = 5.0;          ///< border left out of class areas, m
    double closing_radius_m = 0.25; ///< disk radius of the morphological closing, m
    PsdOptions psd;
    FractalDimensionOptions fd;
    void validate() const;
};

/// Paper 000's missions on a terrain: the Moore-gradient classes of `z`, their closing, and
/// plan_missions() with `m` (its border taken from `opt`). Checks both option sets.
std::vector<Mission> plan_missions(const RasterD& z, const AnalysisOptions& opt, MissionOptions m);

struct TerrainAnalysis {
    RasterStats elevation;
    RmsResult rms;
    ClassAreas classes;        ///< before closing (as the paper reports them)
    ClassAreas closed_classes; ///< after closing
    PsdResult psd;
    FractalDimensionResult fd;
    double mean_slope = 0, max_slope = 0; ///< rise over run
    RasterU8 class_map, closed_class_map;
    /// Figures the cell size makes meaningless, each with why and what to do (scale_notes()).
    std::vector<std::string> notes;
    bool detrended_valid = true, band_limited_valid = true;
    nlohmann::json to_json(const AnalysisOptions& opt) const;
    std::string summary(const AnalysisOptions& opt) const;
};

/// The vehicle-scale windows and radii of `opt` (paper 000 and the US Army's roughness: metres)
/// that a raster of `cell_m` cells cannot resolve: a window or cutoff under two cells, a border or
/// closing disk under one cell, slope classes on cells over 5 m. One note per figure.
std::vector<std::string> scale_notes(const AnalysisOptions& opt, double cell_m);

TerrainAnalysis analyze_terrain(const RasterD& z, const AnalysisOptions& opt = {});

/// Writes hillshade.png, elevation.png, slope.png, gradient_classes.png and closed_classes.png
/// into `dir` (created if missing); returns the paths written.
std::vector<std::filesystem::path> write_analysis_pictures(const RasterD& z,
                                                           const TerrainAnalysis& a,
                                                           const AnalysisOptions& opt,
                                                           const std::filesystem::path& dir);

} // namespace ecoterra::terrain
