#pragma once
// Helpers every test file needs: scratch files in a per-process temporary folder, and the
// check that a call fails with an InputError whose message says what it should.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace room_reverb::test {

// `name` inside a folder of the system's temp directory private to this test process.
std::filesystem::path tempPath(const std::string& name);

// Writes `contents` to tempPath(name) byte for byte and returns the path.
std::string writeFile(const std::string& name, const std::string& contents);

// Fails the test unless `call` throws core::InputError whose message contains every
// fragment.
void expectInputError(const std::function<void()>& call, const std::vector<std::string>& fragments);

}  // namespace room_reverb::test
