#pragma once
// Files in and out, with the errors a user can cause reported as InputError, worded the
// same way by every reader.
#include <string>

namespace room_reverb::core {

// InputError unless `path` names an existing file that is not a directory: "<path>: no
// such file (expected a <what>)[; <hint>]" or "<path>: is a directory, not a <what>".
// `what` says what the file was meant to be ("room model").
void requireExistingFile(const std::string& path, const std::string& what, const std::string& hint = "");

// The file's contents, after requireExistingFile; InputError for an unreadable file.
std::string readTextFile(const std::string& path, const std::string& what);

// Writes `text` (replacing the file). InputError naming the path when it cannot.
void writeTextFile(const std::string& path, const std::string& text);

// Writes `text` as a new file at `path`, whole or not at all: into "<path>.part", synced
// to the disk, then linked to `path`, so that a reader of the folder (or a crash
// mid-write) never sees half a file. False, writing nothing, when `path` (or another
// writer's "<path>.part") exists already: concurrent writers may race for one name, and
// each gets a name of its own by trying the next. InputError when it cannot write.
bool writeNewFileAtomically(const std::string& path, const std::string& text);

// Creates the folder and its parents if missing. InputError naming the path when it cannot
// ("<path>: cannot create the folder: <reason>").
void createFolder(const std::string& path);

// A file the package ships (e.g. "config/materials.yaml"): the value of the environment
// variable `environment_variable` when it is set and not empty, else `relative` in the
// package's source tree (the working directory's when built without ROOM_REVERB_SOURCE_DIR).
std::string packageFilePath(const char* environment_variable, const std::string& relative);

}  // namespace room_reverb::core
