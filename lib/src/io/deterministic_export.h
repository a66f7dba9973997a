// Same scene, same bytes: what assimp's exporters write that does not come from the scene (the
// clock, the temporary path, pointer values) is replaced by fixed values.
#pragma once

#include <string>

namespace untangle {

// (Before export, the assimp module names the unnamed nodes of an X scene, which its exporter
// would otherwise name after their pointers: lib/assimp_module/write.cpp.)

// After export: rewrites `path`, written in format `format_id`, with the creation and
// modification times at 1970-01-01T00:00:00 (Collada <created>/<modified>, FBX
// CreationTimeStamp) and, in an assbin dump, the date and the source path replaced by the zero
// date and `final_name`. Throws Error(kOutputNotWritten) when the file cannot be rewritten.
void finish_deterministic_export(const std::string& format_id, const std::string& path,
                                 const std::string& final_name);

}  // namespace untangle
