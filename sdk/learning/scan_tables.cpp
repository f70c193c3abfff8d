#include "learning/scan_tables.hpp"

#include "common/error.hpp"
#include "common/files.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace ssc::learning {

std::vector<std::string> csv_cells(const std::string& line) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
            else if (c == '"') quoted = false;
            else cells.back() += c;
        } else if (c == '"') quoted = true;
        else if (c == ',') cells.emplace_back();
        else if (c != '\r') cells.back() += c;
    }
    for (auto& cell : cells) {
        while (!cell.empty() && cell.back() == ' ') cell.pop_back();
        while (!cell.empty() && cell.front() == ' ') cell.erase(cell.begin());
    }
    return cells;
}

std::string csv_cell(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' || c == '\r' ? ' ' : c);
    return out + "\"";
}

AttributeTable read_attribute_table(const std::string& path) { return parse_attribute_table(read_regular_file(path, 256ull << 20), path); }

std::map<std::string, PersonDecision> read_decisions(const std::string& path) { return parse_decisions(read_regular_file(path, 64ull << 20), path); }

std::map<std::string, PersonDecision> parse_decisions(const std::string& text, const std::string& path) {
    std::istringstream in(text);
    std::string line;
    std::map<std::string, PersonDecision> out;
    if (!std::getline(in, line) || csv_cells(line).at(0) != "scan")
        throw Error(SSC_ERROR_INVALID_ARGUMENT, path + ": the first line must be the header scan,decision,reason,by");
    for (std::size_t number = 2; std::getline(in, line); ++number) {
        if (line.empty() || line == "\r") continue;
        const std::vector<std::string> c = csv_cells(line);
        const std::string where = path + ":" + std::to_string(number) + ": ";
        if (c.size() < 2 || (c[1] != "accept" && c[1] != "reject"))
            throw Error(SSC_ERROR_INVALID_ARGUMENT, where + "expected scan,accept|reject[,reason[,by]]");
        if (c.size() >= 4 && c[3] == "auto") continue;
        if (!out.emplace(c[0], PersonDecision{c[1] == "accept", c.size() >= 3 ? c[2] : std::string()}).second)
            throw Error(SSC_ERROR_INVALID_ARGUMENT, where + "scan " + c[0] + " is decided twice");
    }
    return out;
}

AttributeTable parse_attribute_table(const std::string& text, const std::string& path) {
    std::istringstream in(text);
    AttributeTable t;
    t.source = std::filesystem::path(path).filename().string();
    std::string line;
    if (!std::getline(in, line)) fail(SSC_ERROR_INVALID_ARGUMENT, path + ": empty; the first line names the columns: scan,NAME,...");
    const std::vector<std::string> header = csv_cells(line);
    if (header.size() < 2 || header[0] != "scan") fail(SSC_ERROR_INVALID_ARGUMENT, path + ": the first line must be scan,NAME,... (the attributes' names)");
    for (std::size_t c = 1; c < header.size(); ++c) {
        if (header[c].empty()) fail(SSC_ERROR_INVALID_ARGUMENT, path + ": column " + std::to_string(c + 1) + " has no name");
        t.names.push_back(header[c]);
    }
    for (std::size_t number = 2; std::getline(in, line); ++number) {
        if (line.empty() || line == "\r") continue;
        const std::vector<std::string> cells = csv_cells(line);
        const std::string where = path + ":" + std::to_string(number);
        if (cells.size() != header.size())
            fail(SSC_ERROR_INVALID_ARGUMENT, where + ": " + std::to_string(cells.size()) + " cells, the header has " + std::to_string(header.size()));
        std::vector<double> values;
        for (std::size_t c = 1; c < cells.size(); ++c) {
            char* end = nullptr;
            const double x = std::strtod(cells[c].c_str(), &end);
            if (cells[c].empty() || *end != '\0' || !std::isfinite(x)) fail(SSC_ERROR_INVALID_ARGUMENT, where + ": '" + cells[c] + "' is not a finite number");
            values.push_back(x);
        }
        if (!t.rows.emplace(cells[0], values).second) fail(SSC_ERROR_INVALID_ARGUMENT, where + ": scan " + cells[0] + " is listed twice");
    }
    return t;
}

std::vector<training::KnownAttribute> attributes_for(const AttributeTable& table, const std::vector<std::string>& scans) {
    std::vector<training::KnownAttribute> out;
    for (const auto& name : table.names) out.push_back({name, "", "Given with the scans (" + table.source + ").", true, {}});
    for (const auto& scan : scans) {
        const auto it = table.rows.find(scan);
        if (it == table.rows.end()) fail(SSC_ERROR_INVALID_ARGUMENT, table.source + ": no row for " + scan);
        for (std::size_t a = 0; a < out.size(); ++a) out[a].values.push_back(it->second[a]);
    }
    return out;
}

}  // namespace ssc::learning
