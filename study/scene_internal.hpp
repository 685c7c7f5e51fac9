#pragma once
// Internal to the scene part (scene_measures.cpp, scene_records.cpp, scene_accuracy.cpp and the
// section's scene_tables.cpp): what its files share. The API is scene_study.hpp.
#include <cstddef>
#include <string>
#include <vector>

#include "scene_study.hpp"

namespace oas::study::detail {

/// scene_equal_time.csv's columns.
extern const std::vector<std::string> kEqualTimeColumns;

/// scene_equal_time.csv's rows (cells in kEqualTimeColumns order); none when the file is absent.
std::vector<std::vector<std::string>> readEqualTimeRows(const std::string& path);

/// Position of a sampler label in studySamplers() (unknown labels after them).
size_t samplerRank(const std::string& label);

/// Position of a scene in studyScenes() (unknown names after them).
size_t sceneRank(const std::string& name);

/// Each record's curves, its points marked capped by its own s.e. target. Every relMSE is the
/// render's error less the reference's own estimated error (refErr), so its s.e. includes the
/// reference's: √(s.e.² + s.e.(refErr)²), with s.e.(refErr) = refErr itself for records that did
/// not measure it (referenceErrorSe came later).
std::vector<SceneCurve> curvesOfRecords(const std::vector<SceneRecord>& records,
                                        const std::vector<SceneMeasurement>& measurements);

/// Every point with its n and standard errors; "capped" = the s.e. target was not reached (full
/// image or crop) before maxTrials. plot.py draws the error bars from the *_se columns.
void writeCurves(const std::string& path, const std::vector<SceneCurve>& curves);

/// outDir's scene_costs.csv, or none.
std::vector<SceneCost> costsIn(const std::string& outDir);

/// Writes outDir's scenes.csv, scene_references.csv and scene_equal_time.csv (its rows put in scene,
/// then table order), then rereads the first two, so that scene_curves.csv and the returned section
/// are built from what the files hold (as --parts none would build them), not from the run's memory.
std::string writeSceneData(const std::string& outDir, const std::vector<SceneRecord>& records,
                           const std::vector<SceneMeasurement>& measurements, std::vector<std::vector<std::string>> equalTimeRows,
                           const std::vector<SamplerSpec>& samplers);

}  // namespace oas::study::detail
