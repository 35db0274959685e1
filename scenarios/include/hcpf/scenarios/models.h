#pragma once
// Model files named in scenarios: where they are looked for, and the
// dimensions of the vehicle or occluder they hold.

#include <Eigen/Core>
#include <string>

#include "hcpf/core/error.h"

namespace hcpf::scenarios {

// Resolves a model path as written in a scenario: an absolute path; else
// relative to the scenario file's folder; else to the current directory; else
// to the project's source folder (so shipped scenarios run from anywhere;
// config::FindFile's order).
// Returns the canonical absolute path of the first candidate that exists;
// throws InputError at `where` naming every place looked at when none exists
// (`expected` the error's "expected"). Other files a scenario names (a
// det.txt) are found the same way.
std::string ResolveModelPath(const std::string& written, const std::string& scenario_file,
                             const SourceLocation& where,
                             const std::string& expected = "the path of an existing model file");

// `file` relative to the project's source folder when inside it, else its
// absolute path: the same whatever the current folder (a sweep's
// meta.sweep_file).
std::string ProjectRelativePath(const std::string& file);

// The path written to resolved scenarios: relative to the project's source
// folder when the file is inside it (shipped assets stay portable), else
// absolute: the same whatever folder hcpf is started from.
std::string PortableModelPath(const std::string& resolved);

// Length (along +x), width and height of a model file's bounding box, in
// metres, read with the renderer's mesh importer. Throws InputError at `where`
// when the file cannot be read as a mesh.
Eigen::Vector3d ModelDimensions(const std::string& path, const SourceLocation& where);

// The content of a model file, as the resolved YAML's `model_digest` pins it:
// XXH3-128 (32 lowercase hex digits) of its bytes, then of each file beside
// it that its loader reads (renderer::ModelSideFiles: a glTF's buffers, an
// .obj's material libraries), by its path relative to the model's folder and
// its bytes. Read anew at each call (no cache: a sweep's child process checks
// the file as it is then). Throws InputError at `where` when a file cannot be
// read.
std::string ModelDigest(const std::string& path, const SourceLocation& where);

}  // namespace hcpf::scenarios
