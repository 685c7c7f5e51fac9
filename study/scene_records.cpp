// The scene part's data files: scene_references.csv (a record per scene: its reference, settings,
// device and date), scenes.csv (every render), scene_equal_time.csv and scene_curves.csv; the
// merging of rows measured apart (scene shards, sampler shards, top-ups, the Dask workers' shards
// of mergeSceneShards); and the section assembled from the files alone.
#include "scene_study.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "scene_costs.hpp"
#include "scene_internal.hpp"
#include "stats.hpp"

namespace oas::study {

using detail::costsIn;
using detail::curvesOfRecords;
using detail::kEqualTimeColumns;
using detail::readEqualTimeRows;
using detail::samplerRank;
using detail::sceneRank;
using detail::writeCurves;
using detail::writeSceneData;

namespace detail {

const std::vector<std::string> kEqualTimeColumns = {"scene", "sampler", "spp", "seconds", "budget_seconds", "rel_mse", "image"};

}  // namespace detail

namespace {

const std::vector<std::string> kMeasurementColumns = {
    "scene",        "sampler",     "pattern",          "spp",           "trial",        "seconds",  "rel_mse",
    "rel_mse_crop", "rel_mse_raw", "rel_mse_crop_raw", "rel_mse_worst", "rel_mse_rare", "rare_only"};

const std::vector<std::string> kRecordColumns = {"scene",
                                                 "width",
                                                 "height",
                                                 "dims",
                                                 "reference_sampler",
                                                 "reference_spp",
                                                 "ref_rel_mse",
                                                 "ref_rel_mse_crop",
                                                 "seconds",
                                                 "crop_x",
                                                 "crop_y",
                                                 "crop_w",
                                                 "crop_h",
                                                 "largest_spp",
                                                 "device",
                                                 "machine",
                                                 "date",
                                                 "command",
                                                 "mode",
                                                 "min_spp",
                                                 "max_spp",
                                                 "paper_spp",
                                                 "min_renders",
                                                 "max_renders",
                                                 "rel_se_target",
                                                 "extra_seconds",
                                                 "run_seconds",
                                                 "rare_count",
                                                 "rare_pixels",
                                                 "ref_rel_mse_se",
                                                 "ref_rel_mse_crop_se"};

/// Whether the file has column `name` (columns added later are optional: older files lack them).
bool hasColumn(const CsvRows& t, const std::string& name)
{
    return std::find(t.header.begin(), t.header.end(), name) != t.header.end();
}

/// `kept` without the rows whose key (keyOf) a row of `fresh` has, then `fresh`, in scene order.
template <class T, class NameOf, class KeyOf>
std::vector<T> mergeByKey(const std::vector<T>& kept, const std::vector<T>& fresh, NameOf nameOf, KeyOf keyOf)
{
    std::vector<T> all;
    for (const auto& k : kept)
        if (std::none_of(fresh.begin(), fresh.end(), [&](const T& f) { return keyOf(f) == keyOf(k); })) all.push_back(k);
    all.insert(all.end(), fresh.begin(), fresh.end());
    // Scene order (studyScenes(), then first appearance); rows keep their order within a scene.
    std::vector<std::string> order;
    for (const auto& a : all)
        if (std::find(order.begin(), order.end(), nameOf(a)) == order.end()) order.push_back(nameOf(a));
    std::stable_sort(order.begin(), order.end(),
                     [](const std::string& a, const std::string& b) { return sceneRank(a) < sceneRank(b); });
    std::vector<T> sorted;
    for (const auto& name : order)
        for (const auto& a : all)
            if (nameOf(a) == name) sorted.push_back(a);
    return sorted;
}

template <class T, class NameOf>
std::vector<T> mergeByScene(const std::vector<T>& kept, const std::vector<T>& fresh, NameOf nameOf)
{
    return mergeByKey(kept, fresh, nameOf, nameOf);
}

}  // namespace

namespace detail {

std::vector<std::vector<std::string>> readEqualTimeRows(const std::string& path)
{
    std::vector<std::vector<std::string>> rows;
    if (!std::filesystem::exists(path)) return rows;
    const CsvRows old = readCsv(path);
    for (const auto& row : old.rows) {
        std::vector<std::string> cells;
        for (const auto& name : kEqualTimeColumns) cells.push_back(row[old.column(name, path)]);
        rows.push_back(cells);
    }
    return rows;
}

size_t samplerRank(const std::string& label)
{
    const auto every = studySamplers();
    return size_t(std::find_if(every.begin(), every.end(), [&](const SamplerSpec& e) { return e.label == label; }) -
                  every.begin());
}

size_t sceneRank(const std::string& name)
{
    const auto cases = studyScenes();
    for (size_t i = 0; i < cases.size(); ++i)
        if (std::filesystem::path(cases[i].file).stem().string() == name) return i;
    return cases.size();
}

void writeCurves(const std::string& path, const std::vector<SceneCurve>& curves)
{
    CsvTable curveCsv({"scene", "sampler", "spp", "seconds", "rel_mse", "rel_mse_crop", "n", "rel_mse_se", "rel_mse_crop_se",
                       "capped", "rel_mse_without_worst", "rel_mse_without_worst_se", "rel_mse_worst", "rel_mse_worst_se",
                       "rare_renders"});
    for (const auto& c : curves)
        for (size_t i = 0; i < c.spp.size(); ++i)
            curveCsv.add({c.scene, c.sampler, fmtG(c.spp[i]), fmtG(c.seconds[i]), fmtG(c.relMse[i]), fmtG(c.relMseCrop[i]),
                          std::to_string(c.relMseE[i].n), fmtG(c.relMseE[i].se), fmtG(c.relMseCropE[i].se),
                          c.relMseE[i].capped || c.relMseCropE[i].capped ? "1" : "0", fmtG(c.relMseRestE[i].mean),
                          fmtG(c.relMseRestE[i].se), fmtG(c.worstE[i].mean), fmtG(c.worstE[i].se),
                          std::to_string(c.rareRenders[i])});
    curveCsv.write(path);
}

std::vector<SceneCost> costsIn(const std::string& outDir)
{
    const std::string path = outDir + "/scene_costs.csv";
    return std::filesystem::exists(path) ? readSceneCosts(path) : std::vector<SceneCost>{};
}

}  // namespace detail

void writeSceneRecords(const std::string& path, const std::vector<SceneRecord>& records)
{
    CsvTable t(kRecordColumns);
    for (const auto& r : records)
        t.add({r.name,
               std::to_string(r.width),
               std::to_string(r.height),
               std::to_string(r.dims),
               r.referenceSampler,
               std::to_string(r.referenceSpp),
               fmtG(r.refErr, 9),
               fmtG(r.refErrCrop, 9),
               fmtG(r.refSeconds),
               std::to_string(r.crop.x),
               std::to_string(r.crop.y),
               std::to_string(r.crop.w),
               std::to_string(r.crop.h),
               std::to_string(r.largestSpp),
               r.device,
               r.machine,
               r.date,
               r.command,
               r.modeLabel,
               std::to_string(r.minSpp),
               std::to_string(r.maxSpp),
               std::to_string(r.paperHighSpp),
               std::to_string(r.minTrials),
               std::to_string(r.maxTrials),
               fmtG(r.relSeTarget),
               fmtG(r.extraSeconds),
               fmtG(r.runSeconds),
               std::to_string(r.rareCount),
               r.rarePixels,
               fmtG(r.refErrSe, 9),
               fmtG(r.refErrCropSe, 9)});
    t.write(path);
}

std::vector<SceneRecord> readSceneRecords(const std::string& path)
{
    const CsvRows t = readCsv(path);
    std::vector<SceneRecord> out;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const auto& row = t.rows[i];
        auto text = [&](const char* name) { return row[t.column(name, path)]; };
        auto num = [&](const char* name) { return csvNumber(t, row, name, path, i); };
        auto cnt = [&](const char* name) { return csvCount(t, row, name, path, i); };
        SceneRecord r;
        r.name = text("scene");
        r.width = cnt("width");
        r.height = cnt("height");
        r.dims = cnt("dims");
        r.referenceSampler = text("reference_sampler");
        r.referenceSpp = cnt("reference_spp");
        r.refErr = num("ref_rel_mse");
        r.refErrCrop = num("ref_rel_mse_crop");
        if (hasColumn(t, "ref_rel_mse_se")) {  // added later; "nan" when a run did not measure it
            r.refErrSe = num("ref_rel_mse_se");
            r.refErrCropSe = num("ref_rel_mse_crop_se");
        }
        r.refSeconds = num("seconds");
        r.crop = {cnt("crop_x"), cnt("crop_y"), cnt("crop_w"), cnt("crop_h")};
        r.largestSpp = cnt("largest_spp");
        r.device = text("device");
        r.machine = text("machine");
        r.date = text("date");
        r.command = text("command");
        r.modeLabel = text("mode");
        r.minSpp = cnt("min_spp");
        r.maxSpp = cnt("max_spp");
        r.paperHighSpp = cnt("paper_spp");
        r.minTrials = cnt("min_renders");
        r.maxTrials = cnt("max_renders");
        r.relSeTarget = num("rel_se_target");
        r.extraSeconds = num("extra_seconds");
        r.runSeconds = num("run_seconds");
        if (hasColumn(t, "rare_count")) r.rareCount = cnt("rare_count");
        if (hasColumn(t, "rare_pixels")) r.rarePixels = text("rare_pixels");
        if (r.name.empty() || r.width == 0 || r.height == 0 || r.crop.w == 0 || r.crop.h == 0 || r.crop.x + r.crop.w > r.width ||
            r.crop.y + r.crop.h > r.height || !(r.relSeTarget > 0))
            throw std::runtime_error(path + ": row " + std::to_string(i + 1) +
                                     ": the scene name, size, crop (inside the image) or s.e. target is invalid");
        try {
            parsePixels(r.rarePixels, r.width, r.height);
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error(path + ": row " + std::to_string(i + 1) + ", column \"rare_pixels\": " + e.what());
        }
        if (std::any_of(out.begin(), out.end(), [&](const SceneRecord& o) { return o.name == r.name; }))
            throw std::runtime_error(path + ": scene \"" + r.name + "\" appears twice");
        out.push_back(std::move(r));
    }
    return out;
}

void writeSceneMeasurements(const std::string& path, const std::vector<SceneMeasurement>& measurements)
{
    CsvTable csv(kMeasurementColumns);
    for (const auto& m : measurements)
        csv.add({m.scene, m.sampler, m.pattern, std::to_string(m.spp), std::to_string(m.trial), fmtG(m.seconds), fmtG(m.relMse),
                 fmtG(m.relMseCrop), fmtG(m.relMseRaw), fmtG(m.relMseCropRaw), fmtG(m.relMseWorst), fmtG(m.relMseRare),
                 m.rareOnly ? "1" : "0"});
    csv.write(path);
}

std::vector<SceneMeasurement> readSceneMeasurements(const std::string& path)
{
    const CsvRows t = readCsv(path);
    std::vector<SceneMeasurement> out;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const auto& row = t.rows[i];
        auto num = [&](const char* name) { return csvNumber(t, row, name, path, i); };
        SceneMeasurement m;
        m.scene = row[t.column("scene", path)];
        m.sampler = row[t.column("sampler", path)];
        m.pattern = row[t.column("pattern", path)];
        m.spp = csvCount(t, row, "spp", path, i);
        m.trial = csvCount(t, row, "trial", path, i);
        m.seconds = num("seconds");
        m.relMse = num("rel_mse");
        m.relMseCrop = num("rel_mse_crop");
        m.relMseRaw = num("rel_mse_raw");
        m.relMseCropRaw = num("rel_mse_crop_raw");
        m.relMseWorst = num("rel_mse_worst");
        if (hasColumn(t, "rel_mse_rare")) m.relMseRare = num("rel_mse_rare");
        if (hasColumn(t, "rare_only")) {
            const std::uint32_t flag = csvCount(t, row, "rare_only", path, i);
            if (flag > 1)
                throw std::runtime_error(path + ": row " + std::to_string(i + 1) +
                                         ", column \"rare_only\": " + std::to_string(flag) + " is not 0 or 1");
            m.rareOnly = flag == 1;
        }
        if (m.spp == 0 || !(m.seconds >= 0))
            throw std::runtime_error(path + ": row " + std::to_string(i + 1) + ": spp must be >= 1 and seconds >= 0");
        out.push_back(std::move(m));
    }
    return out;
}

std::vector<SceneRecord> mergeSceneRecords(const std::vector<SceneRecord>& kept, const std::vector<SceneRecord>& fresh)
{
    return mergeByScene(kept, fresh, [](const SceneRecord& r) { return r.name; });
}

std::vector<SceneMeasurement> mergeSceneMeasurements(const std::vector<SceneMeasurement>& kept,
                                                     const std::vector<SceneMeasurement>& fresh)
{
    return mergeByScene(kept, fresh, [](const SceneMeasurement& m) { return m.scene; });
}

std::vector<SceneMeasurement> mergeSamplerShard(const std::vector<SceneMeasurement>& kept,
                                                const std::vector<SceneMeasurement>& fresh)
{
    return mergeByKey(
        kept, fresh, [](const SceneMeasurement& m) { return m.scene; },
        [](const SceneMeasurement& m) { return std::make_pair(m.scene, m.sampler); });
}

bool sameSceneSettings(const SceneRecord& a, const SceneRecord& b, std::string* why)
{
    auto differs = [&](const char* what, const std::string& x, const std::string& y) {
        if (x == y) return false;
        if (why) *why = std::string(what) + " " + x + " vs " + y;
        return true;
    };
    auto num = [](double v) { return fmtG(v, 9); };
    auto crop = [](const oas::image::Crop& c) {
        return std::to_string(c.w) + "x" + std::to_string(c.h) + "+" + std::to_string(c.x) + "+" + std::to_string(c.y);
    };
    return !(differs("scene", a.name, b.name) ||
             differs("size", std::to_string(a.width) + "x" + std::to_string(a.height),
                     std::to_string(b.width) + "x" + std::to_string(b.height)) ||
             differs("dims", std::to_string(a.dims), std::to_string(b.dims)) || differs("crop", crop(a.crop), crop(b.crop)) ||
             differs("reference", a.referenceSampler + "@" + std::to_string(a.referenceSpp),
                     b.referenceSampler + "@" + std::to_string(b.referenceSpp)) ||
             differs("spp ladder",
                     std::to_string(a.minSpp) + "-" + std::to_string(a.maxSpp) + "/" + std::to_string(a.paperHighSpp),
                     std::to_string(b.minSpp) + "-" + std::to_string(b.maxSpp) + "/" + std::to_string(b.paperHighSpp)) ||
             differs("renders per point", std::to_string(a.minTrials) + "-" + std::to_string(a.maxTrials),
                     std::to_string(b.minTrials) + "-" + std::to_string(b.maxTrials)) ||
             differs("s.e. target", num(a.relSeTarget), num(b.relSeTarget)) || differs("mode", a.modeLabel, b.modeLabel) ||
             differs("rare pixels", std::to_string(a.rareCount), std::to_string(b.rareCount)) ||
             differs("device", a.device, b.device));
}

SceneRecord joinShardRecord(const SceneRecord& kept, const SceneRecord& fresh)
{
    // "a + b", b added only when a does not list it yet.
    auto join = [](const std::string& list, const std::string& item, const std::string& sep) {
        if (list.empty()) return item;
        size_t at = 0;
        while (at <= list.size()) {
            const size_t end = std::min(list.find(sep, at), list.size());
            if (list.compare(at, end - at, item) == 0) return list;
            at = end + sep.size();
        }
        return list + sep + item;
    };
    SceneRecord r = fresh;
    r.referenceSampler = kept.referenceSampler;
    r.referenceSpp = kept.referenceSpp;
    r.refErr = kept.refErr;
    r.refErrCrop = kept.refErrCrop;
    r.refErrSe = kept.refErrSe;
    r.refErrCropSe = kept.refErrCropSe;
    r.refSeconds = kept.refSeconds;
    r.rarePixels = kept.rarePixels;  // chosen with the reference
    r.largestSpp = std::max(kept.largestSpp, fresh.largestSpp);
    r.extraSeconds = kept.extraSeconds + fresh.extraSeconds;
    r.runSeconds = kept.runSeconds + fresh.runSeconds;
    r.date = join(kept.date, fresh.date, " + ");
    r.machine = join(kept.machine, fresh.machine, " + ");
    r.command = join(kept.command, fresh.command, " ; ");
    return r;
}

std::string detail::writeSceneData(const std::string& outDir, const std::vector<SceneRecord>& records,
                                   const std::vector<SceneMeasurement>& measurements,
                                   std::vector<std::vector<std::string>> equalTimeRows, const std::vector<SamplerSpec>& samplers)
{
    const std::string refPath = outDir + "/scene_references.csv", csvPath = outDir + "/scenes.csv";
    // Scene order, then table order (a joined shard's rows would otherwise come last).
    std::stable_sort(equalTimeRows.begin(), equalTimeRows.end(), [&](const auto& a, const auto& b) {
        return std::make_pair(sceneRank(a[0]), samplerRank(a[1])) < std::make_pair(sceneRank(b[0]), samplerRank(b[1]));
    });
    CsvTable equalTime(kEqualTimeColumns);
    for (const auto& row : equalTimeRows) equalTime.add(row);
    writeSceneMeasurements(csvPath, measurements);
    writeSceneRecords(refPath, records);
    equalTime.write(outDir + "/scene_equal_time.csv");
    const auto writtenRecords = readSceneRecords(refPath);
    const auto writtenMeasurements = readSceneMeasurements(csvPath);
    writeCurves(outDir + "/scene_curves.csv", curvesOfRecords(writtenRecords, writtenMeasurements));
    return sceneSection(writtenRecords, writtenMeasurements, samplers, costsIn(outDir));
}

std::string sceneSectionFromFiles(const std::string& outDir, const std::vector<SamplerSpec>& samplers)
{
    const std::string refPath = outDir + "/scene_references.csv", csvPath = outDir + "/scenes.csv";
    if (!std::filesystem::exists(refPath) || !std::filesystem::exists(csvPath)) return "";
    return sceneSection(readSceneRecords(refPath), readSceneMeasurements(csvPath), samplers, costsIn(outDir));
}

std::string mergeSceneShards(const std::string& outDir, const std::string& baseDir, const std::vector<std::string>& shardDirs,
                             const std::vector<SamplerSpec>& samplers, const std::string& command)
{
    namespace fs = std::filesystem;
    auto recordsIn = [](const std::string& dir) { return readSceneRecords(dir + "/scene_references.csv"); };
    auto measurementsIn = [](const std::string& dir) { return readSceneMeasurements(dir + "/scenes.csv"); };
    const std::vector<SceneRecord> base = recordsIn(baseDir);
    std::vector<SceneRecord> joined = base;
    std::vector<SceneMeasurement> measurements = measurementsIn(baseDir);
    std::vector<std::vector<std::string>> eqRows = readEqualTimeRows(baseDir + "/scene_equal_time.csv");
    // A shard's record is joinShardRecord(base, its own run): its own part is what follows the
    // base's text in the listed fields, and its seconds less the base's.
    auto ownPart = [](const std::string& shardText, const std::string& baseText, const std::string& sep) {
        return shardText.size() > baseText.size() + sep.size() && shardText.compare(0, baseText.size(), baseText) == 0
                   ? shardText.substr(baseText.size() + sep.size())
                   : shardText;
    };
    for (const auto& dir : shardDirs) {
        for (const SceneRecord& shard : recordsIn(dir)) {
            const auto b = std::find_if(base.begin(), base.end(), [&](const SceneRecord& r) { return r.name == shard.name; });
            std::string why;
            if (b == base.end())
                why = "the base " + baseDir + " has no record of it";
            else if (!sameSceneSettings(*b, shard, &why) || shard.refErr != b->refErr || shard.refErrCrop != b->refErrCrop ||
                     shard.rarePixels != b->rarePixels)
                why = why.empty() ? "its reference differs from the base's" : why;
            if (!why.empty())
                throw std::runtime_error(dir + ": scene " + shard.name + " is not a shard of " + baseDir + " (" + why + ")");
            SceneRecord own = shard;
            own.runSeconds -= b->runSeconds;
            own.extraSeconds -= b->extraSeconds;
            own.date = ownPart(shard.date, b->date, " + ");
            own.machine = ownPart(shard.machine, b->machine, " + ");
            own.command = ownPart(shard.command, b->command, " ; ");
            for (auto& r : joined)
                if (r.name == shard.name) r = joinShardRecord(r, own);
        }
        measurements = mergeSamplerShard(measurements, measurementsIn(dir));
        // Equal-time rows and pictures: the shard's samplers' rows replace the earlier ones.
        const auto shardEq = readEqualTimeRows(dir + "/scene_equal_time.csv");
        std::vector<std::vector<std::string>> keptEq;
        for (const auto& row : eqRows)
            if (std::none_of(shardEq.begin(), shardEq.end(), [&](const auto& s) { return s[0] == row[0] && s[1] == row[1]; }))
                keptEq.push_back(row);
        keptEq.insert(keptEq.end(), shardEq.begin(), shardEq.end());
        eqRows = std::move(keptEq);
    }
    // Images: the base's (references), then each shard's (its equal-time pictures).
    fs::create_directories(outDir + "/scenes");
    for (const auto& dir : [&] {
             auto all = shardDirs;
             all.insert(all.begin(), baseDir);
             return all;
         }())
        if (fs::is_directory(dir + "/scenes"))
            for (const auto& entry : fs::directory_iterator(dir + "/scenes"))
                fs::copy_file(entry.path(), outDir + "/scenes/" + entry.path().filename().string(),
                              fs::copy_options::overwrite_existing);
    if (!command.empty())
        for (auto& r : joined) r.command = command;
    // The scenes outside the base keep their rows from outDir's earlier files.
    const std::string refPath = outDir + "/scene_references.csv", csvPath = outDir + "/scenes.csv",
                      eqPath = outDir + "/scene_equal_time.csv";
    if (fs::exists(refPath) && fs::exists(csvPath)) {
        joined = mergeSceneRecords(readSceneRecords(refPath), joined);
        measurements = mergeSceneMeasurements(readSceneMeasurements(csvPath), measurements);
        std::vector<std::vector<std::string>> kept;
        for (const auto& row : readEqualTimeRows(eqPath))
            if (std::none_of(base.begin(), base.end(), [&](const SceneRecord& r) { return r.name == row[0]; }))
                kept.push_back(row);
        eqRows.insert(eqRows.begin(), kept.begin(), kept.end());
    }
    return writeSceneData(outDir, joined, measurements, std::move(eqRows), samplers);
}

}  // namespace oas::study
