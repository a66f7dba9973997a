// Same scene, same bytes: what assimp's exporters write that does not come from the scene (the
// clock, the temporary path, pointer values) is replaced by fixed values.
#pragma once

#include <string>

struct aiScene;

namespace untangle {

// Before export in format `format_id` (an assimp exporter id): names every unnamed node
// "node_<k>" (depth first) where the exporter would otherwise name it after its pointer (X).
void prepare_deterministic_export(const std::string& format_id, aiScene& scene);

// After export: rewrites `path`, written in format `format_id`, with the creation and
// modification times at 1970-01-01T00:00:00 (Collada <created>/<modified>, FBX
// CreationTimeStamp) and, in an assbin dump, the date and the source path replaced by the zero
// date and `final_name`. Throws Error(kOutputNotWritten) when the file cannot be rewritten.
void finish_deterministic_export(const std::string& format_id, const std::string& path,
                                 const std::string& final_name);

}  // namespace untangle
