#include "vpsim/core/log.h"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>

namespace vpsim {
namespace {

std::atomic<int>& currentLevel() {
    static std::atomic<int> level{static_cast<int>(LogLevel::Info)};
    return level;
}

void emit(LogLevel level, const char* prefix, const std::string& message) {
    if (static_cast<int>(level) > currentLevel().load()) return;
    static std::mutex mutex;
    std::lock_guard<std::mutex> lock(mutex);
    std::cerr << "vpsim: " << prefix << message << '\n';
}

}  // namespace

void setLogLevel(LogLevel level) {
    currentLevel() = static_cast<int>(level);
}
LogLevel logLevel() {
    return static_cast<LogLevel>(currentLevel().load());
}
void logError(const std::string& message) {
    emit(LogLevel::Error, "error: ", message);
}
void logWarn(const std::string& message) {
    emit(LogLevel::Warn, "warning: ", message);
}
void logInfo(const std::string& message) {
    emit(LogLevel::Info, "", message);
}
void logDebug(const std::string& message) {
    emit(LogLevel::Debug, "debug: ", message);
}

}  // namespace vpsim
