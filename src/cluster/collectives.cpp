#include "vpsim/cluster/collectives.h"

#include <algorithm>
#include <cstring>

#include "vpsim/core/error.h"

namespace vpsim::cluster {

std::vector<double> sumInRankOrder(Communicator& comm, const std::vector<double>& values) {
    const std::string mine(reinterpret_cast<const char*>(values.data()),
                           values.size() * sizeof(double));
    std::vector<double> sum(values.size(), 0.0);
    const std::vector<std::string> parts = comm.gatherBytes(mine);  // on rank 0 only
    for (const std::string& part : parts) {
        if (part.size() != mine.size()) throw Error("sumInRankOrder: ranks passed different sizes");
        for (size_t i = 0; i < sum.size(); ++i) {
            double v;
            std::memcpy(&v, part.data() + i * sizeof(double), sizeof v);
            sum[i] += v;
        }
    }
    std::string bytes(reinterpret_cast<const char*>(sum.data()), sum.size() * sizeof(double));
    bytes = comm.broadcastBytes(bytes);
    std::memcpy(sum.data(), bytes.data(), std::min(bytes.size(), sum.size() * sizeof(double)));
    return sum;
}

std::vector<nlohmann::json> gatherJson(Communicator& comm, const nlohmann::json& mine) {
    std::vector<nlohmann::json> out;
    for (const std::string& text : comm.gatherBytes(mine.dump()))
        out.push_back(nlohmann::json::parse(text));
    return out;
}

int ownerOfItem(size_t index, int ranks) {
    return int(index % size_t(ranks > 0 ? ranks : 1));
}

std::vector<size_t> itemsOfRank(size_t n, int rank, int ranks) {
    std::vector<size_t> items;
    for (size_t i = size_t(rank); i < n; i += size_t(ranks > 0 ? ranks : 1)) items.push_back(i);
    return items;
}

std::vector<std::string> runItems(Communicator& comm, size_t n,
                                  const std::function<std::string(size_t)>& work) {
    // This rank's results, each prefixed by its length, gathered to rank 0 in one message.
    std::string mine;
    for (size_t i : itemsOfRank(n, comm.rank(), comm.ranks())) {
        const std::string result = work(i);
        const uint64_t size = result.size();
        mine.append(reinterpret_cast<const char*>(&size), sizeof size);
        mine += result;
    }
    std::vector<std::string> byRank = comm.gatherBytes(mine);
    std::vector<std::string> out;
    if (!comm.isRoot()) return out;
    out.resize(n);
    for (int r = 0; r < comm.ranks(); ++r) {
        const std::string& bytes = byRank[size_t(r)];
        size_t at = 0;
        for (size_t i : itemsOfRank(n, r, comm.ranks())) {
            uint64_t size = 0;
            std::memcpy(&size, bytes.data() + at, sizeof size);
            out[i] = bytes.substr(at + sizeof size, size_t(size));
            at += sizeof size + size_t(size);
        }
    }
    return out;
}

void streamToRoot(Communicator& comm, int owner, uint64_t total,
                  const std::function<std::string(uint64_t offset, size_t count)>& read,
                  const std::function<void(const std::string&)>& write, size_t chunk) {
    if (chunk == 0) throw Error("streamToRoot: a chunk of no bytes");
    for (uint64_t offset = 0; offset < total; offset += chunk) {
        const size_t count = size_t(std::min<uint64_t>(chunk, total - offset));
        std::string piece;
        if (comm.rank() == owner) {
            piece = read(offset, count);
            if (piece.size() != count)
                throw Error("streamToRoot: rank " + std::to_string(owner) + " read " +
                            std::to_string(piece.size()) + " of " + std::to_string(count) +
                            " bytes at " + std::to_string(offset));
        }
        const std::vector<std::string> pieces = comm.gatherBytes(piece);  // on rank 0 only
        if (comm.isRoot()) write(pieces.at(size_t(owner)));
    }
}

}  // namespace vpsim::cluster
