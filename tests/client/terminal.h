// For the tests of what the CLI draws on a terminal: enough of a VT100 to replay it, and the
// escape sequences of a transcript.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace partita::test {

/// A screen of `columns` x `rows` with a history above it: printable ASCII with autowrap at the
/// last column (xterm's deferred wrap: the cursor stays on the last column until the next
/// character), CR, LF (scrolling the top row into the history at the bottom), CSI n A (cursor
/// up, stopping at the top row), CSI J (erase from the cursor to the end of the screen) and
/// CSI K (erase to the end of the line). Anything else is listed in `unexpected`.
class Terminal {
  public:
    Terminal(int columns, int rows)
        : columns_(std::max(1, columns)), screen_(size_t(std::max(1, rows)), blank()) {}

    void feed(std::string_view bytes) {
        for (char c : bytes) {
            if (state_ == State::Escape) {
                if (c == '[') {
                    state_ = State::Csi;
                    params_.clear();
                } else {
                    unexpected.push_back(std::string("ESC ") + c);
                    state_ = State::Text;
                }
            } else if (state_ == State::Csi) {
                if (c >= 0x40 && c <= 0x7e) {
                    control(c);
                    state_ = State::Text;
                } else {
                    params_ += c;
                }
            } else if (c == '\x1b') {
                state_ = State::Escape;
            } else if (c == '\r') {
                col_ = 0;
                pendingWrap_ = false;
            } else if (c == '\n') {
                lineFeed();
                pendingWrap_ = false;
            } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
                unexpected.push_back("control " + std::to_string(int(c)));
            } else {
                put(c);
            }
        }
    }

    /// The history, then the screen down to its last row with anything on it, as the lines that
    /// were written: a row the text wrapped out of is joined with the next, trailing blanks are
    /// cut.
    std::vector<std::string> lines() const {
        std::vector<Row> all = history_;
        all.insert(all.end(), screen_.begin(), screen_.end());
        std::vector<std::string> out;
        std::string line;
        for (const Row& row : all) {
            line += row.text;
            if (row.wrapped) continue;
            line.erase(line.find_last_not_of(' ') + 1);
            out.push_back(line);
            line.clear();
        }
        while (!out.empty() && out.back().empty()) out.pop_back();
        return out;
    }

    /// Rows of history and screen that the text wrapped out of.
    int wrappedRows() const {
        int n = 0;
        for (const Row& row : history_) n += row.wrapped;
        for (const Row& row : screen_) n += row.wrapped;
        return n;
    }

    std::vector<std::string> unexpected;

  private:
    struct Row {
        std::string text;
        bool wrapped = false;  // continued on the next row
    };
    enum class State { Text, Escape, Csi };

    Row blank() const { return Row{std::string(size_t(columns_), ' ')}; }

    void put(char c) {
        if (pendingWrap_) {
            screen_[size_t(row_)].wrapped = true;
            col_ = 0;
            lineFeed();
            pendingWrap_ = false;
        }
        screen_[size_t(row_)].text[size_t(col_)] = c;
        if (col_ == columns_ - 1)
            pendingWrap_ = true;
        else
            ++col_;
    }

    void lineFeed() {
        if (row_ + 1 < int(screen_.size())) {
            ++row_;
            return;
        }
        history_.push_back(screen_.front());
        screen_.erase(screen_.begin());
        screen_.push_back(blank());
    }

    void control(char final) {
        const bool numeric = std::all_of(params_.begin(), params_.end(),
                                         [](char c) { return c >= '0' && c <= '9'; });
        const int n = params_.empty() || !numeric ? 1 : std::stoi(params_);
        if (final == 'A' && numeric) {
            row_ = std::max(0, row_ - std::max(1, n));
            pendingWrap_ = false;
        } else if (final == 'J' && (params_.empty() || params_ == "0")) {
            eraseLine();
            for (size_t r = size_t(row_) + 1; r < screen_.size(); ++r) screen_[r] = blank();
        } else if (final == 'K' && (params_.empty() || params_ == "0")) {
            eraseLine();
        } else {
            unexpected.push_back("ESC [" + params_ + final);
        }
    }

    void eraseLine() {
        Row& row = screen_[size_t(row_)];
        std::fill(row.text.begin() + col_, row.text.end(), ' ');
        row.wrapped = false;
    }

    int columns_;
    std::vector<Row> history_, screen_;
    int row_ = 0, col_ = 0;
    bool pendingWrap_ = false;
    State state_ = State::Text;
    std::string params_;
};

/// A control sequence "ESC [ params final" of a transcript, at `position` (of its ESC).
struct ControlSequence {
    size_t position = 0, length = 0;
    std::string params;
    char final = 0;
};

/// The control sequences of a transcript, in order. An ESC not followed by '[' yields one with
/// final 0.
inline std::vector<ControlSequence> controlSequences(std::string_view text) {
    std::vector<ControlSequence> out;
    for (size_t i = text.find('\x1b'); i != std::string_view::npos; i = text.find('\x1b', i + 1)) {
        ControlSequence s;
        s.position = i;
        if (i + 1 < text.size() && text[i + 1] == '[') {
            size_t j = i + 2;
            while (j < text.size() && !(text[j] >= 0x40 && text[j] <= 0x7e)) ++j;
            if (j < text.size()) {
                s.params = std::string(text.substr(i + 2, j - i - 2));
                s.final = text[j];
                s.length = j + 1 - i;
            }
        }
        out.push_back(s);
    }
    return out;
}

}  // namespace partita::test
