// nearestKey (declared in core/config.h): the suggestion of unknown-key messages.
#include <algorithm>
#include <cctype>
#include <limits>
#include <string>
#include <vector>

#include "vpsim/core/config.h"

namespace vpsim {

std::string nearestKey(const std::string& key, const std::vector<std::string>& candidates) {
    // Levenshtein distance, case-insensitive; a candidate is "near" within a third of its length.
    auto lower = [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); };
    std::string best;
    size_t bestDistance = std::numeric_limits<size_t>::max();
    for (const std::string& candidate : candidates) {
        std::vector<size_t> row(candidate.size() + 1);
        for (size_t j = 0; j <= candidate.size(); ++j) row[j] = j;
        for (size_t i = 1; i <= key.size(); ++i) {
            size_t diagonal = row[0];
            row[0] = i;
            for (size_t j = 1; j <= candidate.size(); ++j) {
                const size_t above = row[j];
                const size_t substitute = diagonal + (lower(key[i - 1]) != lower(candidate[j - 1]));
                row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
                diagonal = above;
            }
        }
        const size_t distance = row[candidate.size()];
        const size_t longer = std::max(key.size(), candidate.size());
        if (distance < bestDistance && 3 * distance <= longer)
            bestDistance = distance, best = candidate;
    }
    return best;
}

}  // namespace vpsim
