#include "scan_files/cached_result.hpp"

#include "common/files.hpp"

#include <filesystem>

namespace ssc::scan_files {

namespace {

constexpr uint64_t kMaxResultBytes = 64ull << 20;

std::string as_text(const nlohmann::ordered_json& j) { return j.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n"; }

}  // namespace

CachedResult::CachedResult(std::string path, nlohmann::ordered_json key, std::string key_field)
    : path_(std::move(path)), key_field_(std::move(key_field)), key_(std::move(key)) {}

std::optional<nlohmann::ordered_json> CachedResult::find() const {
    std::error_code ec;
    if (!std::filesystem::exists(path_, ec)) return std::nullopt;
    try {
        nlohmann::ordered_json old = nlohmann::ordered_json::parse(read_regular_file(path_, kMaxResultBytes));
        const nlohmann::json as_written = nlohmann::json::parse(key_.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
        if (old.is_object() && nlohmann::json(old.at(key_field_)) == as_written) return old;
    } catch (const std::exception&) {
        // unreadable, malformed or of another kind: made again
    }
    return std::nullopt;
}

std::string CachedResult::store(const nlohmann::ordered_json& fields) const {
    nlohmann::ordered_json j{{key_field_, key_}};
    for (const auto& [name, value] : fields.items()) j[name] = value;
    const std::string text = as_text(j);
    write_file_atomically(path_, text.data(), text.size());
    return text;
}

void CachedResult::forget() const {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
}

}  // namespace ssc::scan_files
