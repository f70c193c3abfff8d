// libFuzzer targets for the JSON and CSV files the scan tools read, over bytes in memory, chosen
// when compiled (tests/fuzz/CMakeLists.txt):
//   SSC_FUZZ_REPORT   a registration report (scan_files::parse_registration_report, the built-in
//                     model): what learn, evaluate and bootstrap read beside each mesh, its fit included
//   otherwise         a scan table: the first byte picks a decisions CSV ('d') or an attributes CSV
//                     (anything else; then every row's attributes are taken, as learning does)
// A malformed file must give ssc::Error with a status; anything else (a crash, a sanitizer report,
// another exception, a hang, unbounded memory, SSC_ERROR_INTERNAL) is a finding.
#include "common/error.hpp"
#include "scan_files/registration_record.hpp"
#include "learning/scan_tables.hpp"

#ifdef SSC_FUZZ_REPORT
#include "capi/cpp_access.hpp"
#endif

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
#ifdef SSC_FUZZ_REPORT
        static ssc_model* model = [] {
            ssc_model* m = nullptr;
            if (ssc_model_load_default(nullptr, &m) != SSC_OK) __builtin_trap();
            return m;
        }();
        ssc::scan_files::parse_registration_report(text, "fuzz.json", ssc::model_of(model), size % 2 == 0);
#else
        if (!text.empty() && text[0] == 'd') {
            ssc::learning::parse_decisions(text.substr(1), "fuzz.csv");
        } else {
            const ssc::learning::AttributeTable table = ssc::learning::parse_attribute_table(text.empty() ? text : text.substr(1), "fuzz.csv");
            std::vector<std::string> scans;
            for (const auto& row : table.rows) scans.push_back(row.first);
            ssc::learning::attributes_for(table, scans);
        }
#endif
    } catch (const ssc::Error& e) {
        if (e.status() == SSC_ERROR_INTERNAL) __builtin_trap();  // a broken postcondition, not bad input
    }
    return 0;
}
