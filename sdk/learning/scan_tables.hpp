// The CSV tables that come with a scan collection: known attributes per scan (sex, age, anything
// numeric) for learning, and the CSV cells that bootstrapping's decisions files are made of.
// Cells are separated by commas and may be quoted ("a, b" and "" for a quote inside), as
// spreadsheets write them.
#pragma once

#include "training/attributes.hpp"

#include <map>
#include <string>
#include <vector>

namespace ssc::learning {

// One line's cells, trimmed of surrounding spaces; and one cell written, quoted where needed.
std::vector<std::string> csv_cells(const std::string& line);
std::string csv_cell(const std::string& text);

// A header scan,NAME,..., then one row per scan, named by its file stem, numbers only.
struct AttributeTable {
    std::string source;  // the file's name, for the model's descriptions
    std::vector<std::string> names;
    std::map<std::string, std::vector<double>> rows;  // by scan
};

// Throws ssc::Error: IO; INVALID_ARGUMENT for an empty file, a header other than scan,NAME,..., a
// row of another length, a cell that is not a finite number, or a scan listed twice.
AttributeTable read_attribute_table(const std::string& path);
// The same over the file's text (`path` names it in messages; what the fuzz target feeds).
AttributeTable parse_attribute_table(const std::string& text, const std::string& path);

// A person's verdict on a scan (a bootstrapping's decisions.csv, edited): accept or reject, and why.
struct PersonDecision {
    bool accept = false;
    std::string reason;
};

// A decisions CSV: header scan,decision,reason,by, then rows scan,accept|reject[,reason[,by]]. Rows
// whose `by` is "auto" are the tool's own verdicts and are skipped, so a person can edit a round's
// decisions.csv (a row's decision, and its by to "person") and pass it back. Throws ssc::Error: IO;
// INVALID_ARGUMENT for another header, a row without a verdict, or a scan decided twice.
std::map<std::string, PersonDecision> read_decisions(const std::string& path);
std::map<std::string, PersonDecision> parse_decisions(const std::string& text, const std::string& path);

// The attributes of these scans, in their order, each given as a slider candidate. Throws
// ssc::Error (INVALID_ARGUMENT) naming the first scan without a row.
std::vector<training::KnownAttribute> attributes_for(const AttributeTable& table, const std::vector<std::string>& scans);

}  // namespace ssc::learning
