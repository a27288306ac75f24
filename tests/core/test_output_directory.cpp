// Output directories: files written atomically, manifest.json last with sizes and SHA-256, a new
// run removes the old manifest and stale temporaries, and verification trusts only a directory
// whose manifest matches (simulated interruptions included).
#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "vpsim/core/error.h"
#include "vpsim/core/io.h"
#include "vpsim/core/output_directory.h"

using namespace vpsim;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

fs::path freshDirectory(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("vpsim_outdir_" + name);
    fs::remove_all(dir);
    return dir;
}

void runComplete(const fs::path& dir, const std::string& planText) {
    OutputDirectory out(dir.string(), {{"job", "test"}});
    out.writeFile("plan.json", planText);
    out.writeStream("report.json", [](std::ostream& s) { s << "{\"ok\": true}\n"; });
    out.writePath("kernel/table.bin", [](const std::string& temporary) {
        std::ofstream(temporary, std::ios::binary) << std::string(3000, '\x7f');
    });
    out.finish();
}

}  // namespace

TEST_CASE("SHA-256 matches the FIPS 180-2 test vectors", "[core][output]") {
    CHECK(sha256Hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    CHECK(sha256Hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    CHECK(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    const fs::path file = fs::temp_directory_path() / "vpsim_sha_million_a";
    std::ofstream(file, std::ios::binary) << std::string(1000000, 'a');
    CHECK(sha256OfFile(file.string()) ==
          "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("a finished run verifies; any change to a listed file does not", "[core][output]") {
    const fs::path dir = freshDirectory("complete");
    runComplete(dir, "{\"layers\": []}\n");
    OutputVerification ok = verifyOutputDirectory(dir.string());
    REQUIRE(ok.ok);
    CHECK(ok.entries.size() == 3);
    CHECK(ok.runInfo["job"] == "test");
    CHECK(ok.entries[2].name == "kernel/table.bin");
    CHECK(ok.entries[2].bytes == 3000);

    fs::resize_file(dir / "plan.json", 3);  // truncated
    OutputVerification truncated = verifyOutputDirectory(dir.string());
    CHECK_FALSE(truncated.ok);
    CHECK_THAT(truncated.reason, Contains("plan.json") && Contains("size 3"));

    runComplete(dir, "{\"layers\": []}\n");
    std::fstream(dir / "report.json", std::ios::in | std::ios::out | std::ios::binary) << "X";
    OutputVerification changed = verifyOutputDirectory(dir.string());
    CHECK_FALSE(changed.ok);
    CHECK_THAT(changed.reason, Contains("report.json") && Contains("SHA-256"));
    CHECK(verifyOutputDirectory(dir.string(), false).ok);  // same size: only the hash tells

    runComplete(dir, "{\"layers\": []}\n");
    fs::remove(dir / "kernel/table.bin");
    CHECK_THAT(verifyOutputDirectory(dir.string()).reason, Contains("missing"));
    CHECK_THROWS_WITH(requireVerifiedOutputDirectory(dir.string()),
                      Contains("not a complete vpsim output directory"));
}

TEST_CASE("an interrupted rerun leaves a directory that is not trusted", "[core][output]") {
    const fs::path dir = freshDirectory("interrupted");
    runComplete(dir, "{\"old\": 1}\n");
    REQUIRE(verifyOutputDirectory(dir.string()).ok);
    // A killed run leaves a temporary behind (its process, pid 99999999, no longer exists).
    std::ofstream(dir / "plan.json.tmp.99999999") << "partial";
    std::ofstream(dir / "kernel" / "table.bin.tmp.99999998") << "partial";
    std::ofstream(dir / "notes.tmp.txt") << "not a temporary of ours";
    {
        OutputDirectory rerun(dir.string());
        // Begin removed the old manifest and the stale temporaries, nothing else.
        CHECK_FALSE(fs::exists(dir / MANIFEST_NAME));
        CHECK_FALSE(fs::exists(dir / "plan.json.tmp.99999999"));
        CHECK_FALSE(fs::exists(dir / "kernel" / "table.bin.tmp.99999998"));
        CHECK(fs::exists(dir / "notes.tmp.txt"));
        rerun.writeFile("plan.json", "{\"new\": 2}\n");
        // Killed here: no finish(). The new plan.json sits beside the old report.json.
    }
    OutputVerification mixed = verifyOutputDirectory(dir.string());
    CHECK_FALSE(mixed.ok);
    CHECK_THAT(mixed.reason, Contains("no manifest.json"));
    // The next complete run is trusted again.
    runComplete(dir, "{\"new\": 3}\n");
    CHECK(verifyOutputDirectory(dir.string()).ok);
    CHECK(readFile((dir / "plan.json").string()) == "{\"new\": 3}\n");
}

TEST_CASE("manifests and names cannot point outside the directory", "[core][output]") {
    const fs::path dir = freshDirectory("names");
    OutputDirectory out(dir.string());
    CHECK_THROWS_AS(out.path("../escape.json"), InputError);
    CHECK_THROWS_AS(out.path("/etc/passwd"), InputError);
    CHECK_THROWS_AS(out.path(MANIFEST_NAME), InputError);
    out.finish();
    CHECK_THROWS(out.finish());
    CHECK(verifyOutputDirectory(dir.string()).ok);  // an empty run is a valid, empty set

    writeFileAtomic((dir / MANIFEST_NAME).string(),
                    R"({"format": "vpsim-output-manifest-1", "complete": true, "files": [)"
                    R"({"name": "../../etc/passwd", "bytes": 1, "sha256": "00"}]})");
    CHECK_THAT(verifyOutputDirectory(dir.string()).reason, Contains("outside the directory"));
    writeFileAtomic((dir / MANIFEST_NAME).string(), "{\"format\": 1");
    CHECK_THAT(verifyOutputDirectory(dir.string()).reason, Contains("unreadable manifest"));
}

TEST_CASE("files written by any atomic writer inside the directory are recorded",
          "[core][output]") {
    const fs::path dir = freshDirectory("observed");
    const fs::path outside = fs::temp_directory_path() / "vpsim_outdir_outside.json";
    {
        OutputDirectory out(dir.string(), {{"job", "observed"}});
        createDirectories((dir / "kernel").string());
        writeFileAtomic((dir / "plan.json").string(), "{}\n");  // code unaware of manifests
        writeStreamAtomic((dir / "kernel" / "kernel.json").string(),
                          [](std::ostream& s) { s << "{\"k\": 1}"; });
        writeFileAtomic(outside.string(), "elsewhere");  // a cache outside the run: not listed
        writeFileAtomic((dir / "plan.json").string(), "{\"v\": 2}\n");  // rewritten: listed once
        writeFileAtomic((dir / "gone.txt").string(), "x");
        fs::remove(dir / "gone.txt");  // removed by the run itself: not listed
        out.finish();
        REQUIRE(out.entries().size() == 2);
        CHECK(out.entries()[0].name == "plan.json");
        CHECK(out.entries()[0].bytes == 9);
        CHECK(out.entries()[1].name == "kernel/kernel.json");
    }
    CHECK(verifyOutputDirectory(dir.string()).ok);
    // After finish (and destruction) nothing is observed any more.
    writeFileAtomic((dir / "late.txt").string(), "late");
    CHECK(verifyOutputDirectory(dir.string()).entries.size() == 2);
}

TEST_CASE("a run killed with SIGKILL mid-write leaves nothing that verifies", "[core][output]") {
    const fs::path dir = freshDirectory("killed");
    runComplete(dir, "{\"old\": 1}\n");
    REQUIRE(verifyOutputDirectory(dir.string()).ok);
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {  // the run: rewrites plan.json, then dies while writing report.json
        OutputDirectory out(dir.string());
        out.writeFile("plan.json", "{\"new\": 2}\n");
        std::ofstream partial(dir / ("report.json.tmp." + std::to_string(::getpid())));
        partial << "{\"trunc" << std::flush;
        for (;;) ::pause();
    }
    const fs::path marker = dir / ("report.json.tmp." + std::to_string(child));
    for (int i = 0; i < 500 && !fs::exists(marker); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    REQUIRE(WIFSIGNALED(status));
    CHECK(fs::exists(marker));
    CHECK(readFile((dir / "plan.json").string()) == "{\"new\": 2}\n");  // new beside old...
    CHECK_FALSE(verifyOutputDirectory(dir.string()).ok);                // ...and not trusted
    {
        OutputDirectory rerun(dir.string());
        CHECK_FALSE(fs::exists(marker));  // the dead run's temporary is cleaned
    }
    runComplete(dir, "{\"new\": 3}\n");
    CHECK(verifyOutputDirectory(dir.string()).ok);
}
