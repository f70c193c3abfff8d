// A result kept on disk with the key it was made from (the digests of its inputs and its settings):
// reused while the key is the same, made again when anything in it changed. Registrations that
// failed, posture fits and bootstrap rounds are kept this way, so a resumed or distributed run
// redoes only what changed.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace ssc::scan_files {

class CachedResult {
public:
    // The result's JSON file, its key, and the field of the file that holds the key.
    CachedResult(std::string path, nlohmann::ordered_json key, std::string key_field = "key");

    // The file's JSON object when it holds this key; nothing when the file is absent, unreadable,
    // malformed or made from another key. Keys are compared as written (a file name's bytes that
    // are not UTF-8 are written as U+FFFD) and regardless of the order of their fields.
    std::optional<nlohmann::ordered_json> find() const;

    // Writes the key, then `fields`, atomically (ssc::Error IO); returns the text written.
    std::string store(const nlohmann::ordered_json& fields) const;

    // Removes the file (a result made again without one to keep).
    void forget() const;

    const nlohmann::ordered_json& key() const { return key_; }

private:
    std::string path_, key_field_;
    nlohmann::ordered_json key_;
};

}  // namespace ssc::scan_files
