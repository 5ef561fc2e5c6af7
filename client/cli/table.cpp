#include "cli/table.h"

#include <algorithm>
#include <cmath>

namespace partita::cli {

void Table::addRow(std::vector<std::string> cells) {
    cells.resize(headers_.size());
    rows_.push_back(std::move(cells));
}

namespace {

/// Text from the server (labels, scene names) may hold terminal escapes: show them as '?'.
std::vector<std::string> printable(std::vector<std::string> cells) {
    for (auto& cell : cells)
        for (char& ch : cell)
            if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) ch = '?';
    return cells;
}

}  // namespace

void Table::print(std::FILE* out) const {
    const std::vector<std::string> headers = printable(headers_);
    std::vector<std::vector<std::string>> rows;
    for (const auto& r : rows_) rows.push_back(printable(r));
    std::vector<size_t> width(headers.size());
    for (size_t c = 0; c < headers.size(); ++c) {
        width[c] = headers[c].size();
        for (const auto& r : rows) width[c] = std::max(width[c], r[c].size());
    }
    auto line = [&](const std::vector<std::string>& cells) {
        std::string s;
        for (size_t c = 0; c < cells.size(); ++c) {
            s += cells[c];
            if (c + 1 < cells.size()) s += std::string(width[c] - cells[c].size() + 2, ' ');
        }
        std::fprintf(out, "%s\n", s.c_str());
    };
    line(headers);
    for (const auto& r : rows) line(r);
    std::fflush(out);
}

std::string Table::csv() const {
    auto field = [](const std::string& f) {
        if (f.find_first_of(",\"\n\r") == std::string::npos) return f;
        std::string q = "\"";
        for (char c : f) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    };
    std::string out;
    auto line = [&](const std::vector<std::string>& cells) {
        for (size_t c = 0; c < cells.size(); ++c) {
            if (c) out += ',';
            out += field(cells[c]);
        }
        out += "\n";
    };
    line(headers_);
    for (const auto& r : rows_) line(r);
    return out;
}

std::string formatNumber(double value) {
    if (std::isnan(value)) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", value);
    return buf;
}

std::string formatCount(double value) {
    if (std::isnan(value)) return "-";
    char buf[64];
    if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 1e15)
        std::snprintf(buf, sizeof buf, "%.0f", value);
    else
        std::snprintf(buf, sizeof buf, "%.10g", value);
    return buf;
}

}  // namespace partita::cli
