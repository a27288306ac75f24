// The memory budget (core/resources.h): it comes from the RunContext, never from the environment
// (the CLI reads VPSIM_MEMORY_LIMIT; tests/cli/run_cli_tests.sh checks that side), and a memory
// size is a number with one optional K/M/G suffix and nothing else.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/run_context.h"

using namespace vpsim;
using Catch::Matchers::Contains;

namespace {

std::string errorOf(const char* text) {
    try {
        parseMemorySize(text, "VPSIM_MEMORY_LIMIT");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

/// Sets an environment variable for one scope, restoring the previous value.
struct ScopedEnv {
    std::string name;
    bool had = false;
    std::string old;
    ScopedEnv(const char* n, const char* value) : name(n) {
        if (const char* previous = std::getenv(n)) had = true, old = previous;
        ::setenv(n, value, 1);
    }
    ~ScopedEnv() {
        had ? void(::setenv(name.c_str(), old.c_str(), 1)) : void(::unsetenv(name.c_str()));
    }
};

}  // namespace

TEST_CASE("memory checks count bytes against the context's budget and name the fix",
          "[core][resources]") {
    const RunContext defaults;
    CHECK_NOTHROW(checkMemory(defaults, 1024, "a small grid", "nothing"));
    CHECK_THROWS_AS(checkMemory(defaults, 1e30, "a huge grid", "use a coarser voxel"),
                    ResourceError);
    CHECK_THROWS_WITH(checkMemory(defaults, 1e30, "a huge grid", "use a coarser voxel"),
                      Contains("a huge grid would need") && Contains("use a coarser voxel") &&
                          Contains("half the memory"));
    RunContext limited;
    limited.memoryLimit = 1 << 20;
    CHECK(memoryBudget(limited) == (1u << 20));
    CHECK_NOTHROW(checkMemory(limited, 1 << 20, "a grid", "nothing"));
    CHECK_THROWS_WITH(checkMemory(limited, (1 << 20) + 1, "a grid", "use less"),
                      Contains("1 MiB allowed (set by VPSIM_MEMORY_LIMIT)"));
    CHECK_THROWS_AS(checkMemory(limited, std::nan(""), "a grid", "use less"), ResourceError);
}

TEST_CASE("the default budget is half the memory, between 256 MiB and 16 GiB",
          "[core][resources]") {
    const uint64_t budget = defaultMemoryBudget();
    CHECK(budget >= (uint64_t(256) << 20));
    CHECK(budget <= (uint64_t(16) << 30));
    CHECK(memoryBudget(RunContext{}) == budget);
}

TEST_CASE("the library reads no VPSIM_MEMORY_LIMIT", "[core][resources]") {
    const ScopedEnv env("VPSIM_MEMORY_LIMIT", "1K");
    CHECK(memoryBudget(RunContext{}) == defaultMemoryBudget());
    CHECK(defaultMemoryBudget() > 1024);
    CHECK_NOTHROW(checkMemory(RunContext{}, 1 << 20, "a grid", "nothing"));
}

TEST_CASE("memory sizes: bytes or K, M, G, and nothing after", "[core][resources]") {
    CHECK(parseMemorySize("1073741824", "X") == (uint64_t(1) << 30));
    CHECK(parseMemorySize("5G", "X") == (uint64_t(5) << 30));
    CHECK(parseMemorySize("5g", "X") == (uint64_t(5) << 30));
    CHECK(parseMemorySize("512M", "X") == (uint64_t(512) << 20));
    CHECK(parseMemorySize("64k", "X") == (uint64_t(64) << 10));
    CHECK(parseMemorySize("1.5G", "X") == (uint64_t(3) << 29));
    CHECK(parseMemorySize("1e6", "X") == 1000000);
    for (const char* bad : {"5GB?", "5GB", "abc", "5 G x", "5 G", " 5G", "5G ", "-5G", "0", "0M",
                            "0.1", "", "G", "0x10", "inf", "nan", "5T", "1e30G"}) {
        INFO("'" << bad << "'");
        const std::string message = errorOf(bad);
        CHECK_THAT(message, Contains("VPSIM_MEMORY_LIMIT: "));
        CHECK(message.find('\n') == std::string::npos);
    }
    CHECK_THAT(errorOf("5GB?"), Contains("unexpected text after the number") &&
                                    Contains("'5GB?'") && Contains("e.g. 512M or 5G"));
    CHECK_THAT(errorOf("-1M"), Contains("positive"));
}
