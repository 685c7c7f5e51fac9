// Parsing a scene file's text into JSON with a path tracker: duplicate keys are errors (nlohmann
// would keep the last silently) and errors inside the parser (number overflow, syntax) can name
// the JSON path they happened at.
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "scene/scene_fields.hpp"

namespace oas::scene::detail {

namespace {

struct PathTracker {
    struct Frame {
        bool object = true;
        std::string key;
        long long index = -1;
        std::set<std::string> keys;
    };
    std::vector<Frame> frames;

    std::string path(bool pendingArrayElement = false) const
    {
        std::string out;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const Frame& f = frames[i];
            if (f.object) {
                if (!f.key.empty()) out = child(out, f.key);
            } else {
                const long long idx = (pendingArrayElement && i + 1 == frames.size()) ? f.index + 1 : f.index;
                if (idx >= 0) out = element(out, std::size_t(idx));
            }
        }
        return out;
    }
};

struct DuplicateKey {
    std::string path, key;
};

/// Scene files nest a few levels (shapes[3].center); deeper input is an error, found while parsing,
/// so nothing downstream (messages, destructors) ever walks an adversarially deep tree.
constexpr std::size_t kMaxJsonDepth = 64;
struct TooDeep {
    std::string path;
};

}  // namespace

json parseJson(const std::string& text, const std::string& file)
{
    // nlohmann's parser stops at a NUL byte as if the text ended there, so "valid JSON\0garbage"
    // would load; JSON text cannot contain a raw NUL anyway.
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw SceneError(file, {}, fmt::format("malformed JSON: a NUL byte at offset {}: valid JSON text (UTF-8, no NUL)", nul));
    PathTracker tracker;
    auto callback = [&](int, json::parse_event_t event, json& parsed) -> bool {
        using E = json::parse_event_t;
        auto beginElement = [&] {
            if (!tracker.frames.empty() && !tracker.frames.back().object) ++tracker.frames.back().index;
        };
        switch (event) {
        case E::object_start:
        case E::array_start:
            beginElement();
            if (tracker.frames.size() >= kMaxJsonDepth) throw TooDeep{tracker.path()};
            tracker.frames.push_back({event == E::object_start, {}, -1, {}});
            break;
        case E::object_end:
        case E::array_end:
            if (!tracker.frames.empty()) tracker.frames.pop_back();
            break;
        case E::key: {
            auto& frame = tracker.frames.back();
            std::string key = parsed.get<std::string>();
            if (!frame.keys.insert(key).second) {
                frame.key.clear();
                throw DuplicateKey{tracker.path(), key};
            }
            frame.key = std::move(key);
            break;
        }
        case E::value:
            beginElement();
            break;
        }
        return true;
    };
    try {
        return json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/false);
    } catch (const TooDeep& d) {
        throw SceneError(file, d.path,
                         fmt::format("JSON nested deeper than {} levels: valid at most {} levels of arrays and objects",
                                     kMaxJsonDepth, kMaxJsonDepth));
    } catch (const DuplicateKey& d) {
        throw SceneError(file, child(d.path, d.key), fmt::format("duplicate key \"{}\": valid each key once per object", d.key));
    } catch (const json::parse_error& e) {
        std::string why = e.what();
        if (auto pos = why.find("] "); pos != std::string::npos) why = why.substr(pos + 2);
        const std::string near = tracker.path(true);
        throw SceneError(file, {}, fmt::format("malformed JSON: {}{}", why, near.empty() ? "" : " (near " + near + ")"));
    } catch (const json::out_of_range& e) {
        // nlohmann reports 1e999 and the like as a number overflow: not a finite number.
        std::string why = e.what();
        if (auto pos = why.find("] "); pos != std::string::npos) why = why.substr(pos + 2);
        throw SceneError(file, tracker.path(true), fmt::format("{}: valid finite 32-bit floats (|x| < 3.4e38)", why));
    } catch (const json::exception& e) {
        throw SceneError(file, tracker.path(true), fmt::format("malformed JSON: {}", e.what()));
    }
}

}  // namespace oas::scene::detail
