// A plain text table for the terminal (columns padded, two spaces apart) that can also be
// written as CSV.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace partita::cli {

class Table {
  public:
    explicit Table(std::vector<std::string> headers) : headers_(std::move(headers)) {}
    void addRow(std::vector<std::string> cells);
    size_t rows() const { return rows_.size(); }
    void print(std::FILE* out) const;
    /// RFC 4180: fields with a comma, quote or newline are quoted.
    std::string csv() const;

  private:
    std::vector<std::string> headers_;
    std::vector<std::vector<std::string>> rows_;
};

/// "%.6g", and "-" for a NaN.
std::string formatNumber(double value);
/// A count or limit as a plain number: "65536", "1048576", "0.5" (never "1.04858e+06").
std::string formatCount(double value);

}  // namespace partita::cli
