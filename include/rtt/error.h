// rtt::Error: the one channel for bad user input (files, JSON, command line, limits).
// Thrown by the library, caught once at the program edge and printed as one line.
#pragma once

#include <stdexcept>
#include <string>

namespace rtt {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
    /// An error located in a file: "file:line: message" (line 0 = no line known).
    Error(const std::string& file, int line, const std::string& message)
        : std::runtime_error(located(file, line, message)) {}

private:
    static std::string located(const std::string& file, int line, const std::string& message) {
        std::string text = file;
        if (line > 0) text.append(":").append(std::to_string(line));
        return text.append(": ").append(message);
    }
};

}  // namespace rtt
