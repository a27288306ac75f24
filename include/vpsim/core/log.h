#pragma once
/// @file
/// Minimal leveled logging to stderr. Level from setLogLevel() (the CLI maps VPSIM_LOG and
/// -q/-v onto it); default info.

#include <string>

namespace vpsim {

enum class LogLevel { Error = 0, Warn = 1, Info = 2, Debug = 3 };

void setLogLevel(LogLevel level);
LogLevel logLevel();
void logError(const std::string& message);
void logWarn(const std::string& message);
void logInfo(const std::string& message);
void logDebug(const std::string& message);

}  // namespace vpsim
