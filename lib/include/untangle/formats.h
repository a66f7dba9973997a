// The file formats untangle reads and writes (`untangle formats`).
#pragma once

#include <string>
#include <vector>

namespace untangle {

struct FileFormat {
  std::string extension;    // lower case, without the dot: "obj", "gltf"
  std::string description;  // the reader's or writer's name, and how untangle uses it
};

// Every extension read_meshes accepts, sorted by extension: OBJ and plain OFF by untangle
// itself, everything else through assimp's importers (one entry per extension, the first
// importer that claims it).
std::vector<FileFormat> readable_formats();

// Every extension write_meshes writes and can_write accepts, sorted: OBJ and OFF by untangle
// (edited copies of an OBJ or plain OFF input), the others through assimp's exporters, limited
// to those whose files assimp reads back as meshes, because every output is verified by reading
// it back.
std::vector<FileFormat> writable_formats();

}  // namespace untangle
