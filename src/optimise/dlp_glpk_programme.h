#pragma once
// A thin owner of a GLPK problem (private to the optimise module's GLPK users).
#include <glpk.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

namespace vpsim::optimise::detail {

/// A GLPK problem (minimisation) with 1-based column/row helpers.
class Programme {
public:
    Programme() : mP(glp_create_prob(), glp_delete_prob) { glp_set_obj_dir(mP.get(), GLP_MIN); }
    int column(double lo, double hi, double cost, bool binary = false) {
        int j = glp_add_cols(mP.get(), 1);
        glp_set_col_bnds(mP.get(), j, lo == hi ? GLP_FX : (std::isinf(hi) ? GLP_LO : GLP_DB), lo,
                         hi);
        glp_set_obj_coef(mP.get(), j, cost);
        if (binary) glp_set_col_kind(mP.get(), j, GLP_BV);
        return j;
    }
    /// Row sum(coef x) with type GLP_LO (>= lo), GLP_UP (<= hi) or GLP_FX (= lo).
    void row(const std::vector<std::pair<int, double>>& terms, int type, double lo, double hi) {
        int i = glp_add_rows(mP.get(), 1);
        std::vector<int> index{0};
        std::vector<double> value{0.0};
        for (const auto& [j, c] : terms) index.push_back(j), value.push_back(c);
        glp_set_mat_row(mP.get(), i, int(terms.size()), index.data(), value.data());
        glp_set_row_bnds(mP.get(), i, type, lo, hi);
    }
    glp_prob* get() { return mP.get(); }

private:
    std::unique_ptr<glp_prob, void (*)(glp_prob*)> mP;
};

}  // namespace vpsim::optimise::detail
