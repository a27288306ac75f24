// A distributed run keeps each tile's share of cured.stl in the rank's temporary directory:
// checkTileScratch refuses, before any tile, when a rank's has not that much room.
#include <catch2/catch.hpp>

#include "vpsim/cluster/communicator.h"
#include "vpsim/core/error.h"
#include "vpsim/pipeline/cluster_run.h"

using namespace vpsim;

TEST_CASE("a rank without room for a tile's triangles is named before any tile", "[pipeline]") {
    cluster::SingleProcess one;
    CHECK(pipeline::checkTileScratch(one, 0.0));
    CHECK(pipeline::checkTileScratch(one, 1e3));
    CHECK_THROWS_AS(pipeline::checkTileScratch(one, 1e18), ResourceError);
    CHECK_THROWS_WITH(pipeline::checkTileScratch(one, 1e18),
                      Catch::Contains("too little room on rank 0 (") &&
                          Catch::Contains("point TMPDIR at a larger disk"));
}
