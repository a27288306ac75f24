#pragma once
// A thin owner of a GLPK problem (private to the optimise module's GLPK users).
#include <glpk.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "vpsim/optimise/dlp/geometric.h"

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

/// The rows both per-layer geometric programmes share (geometric.h): the print-through
/// recursion D_k = x_k + r D_{k+1}, the soft gel conditions (one slack of cost violationWeight per
/// layer: D >= 1 inside, D <= 1 - margin outside, in units of Ec) and the spread bounds of D inside
/// (two columns of cost +-spreadWeight). x[k]: the dose column of solid layer k; d[k]: D_k's.
inline void addPrintThroughRows(Programme& lp, const std::vector<uint8_t>& solid, double r,
                                const std::vector<int>& x, const std::vector<int>& d,
                                const DlpGeometricOptions& o) {
    const size_t n = solid.size();
    const int dMax = lp.column(0.0, INFINITY, o.spreadWeight),
              dMin = lp.column(0.0, INFINITY, -o.spreadWeight);
    for (size_t k = 0; k < n; ++k) {
        std::vector<std::pair<int, double>> rec{{d[k], 1.0}};
        if (k + 1 < n) rec.push_back({d[k + 1], -r});
        if (solid[k]) rec.push_back({x[k], -1.0});
        lp.row(rec, GLP_FX, 0.0, 0.0);
        const int slack = lp.column(0.0, INFINITY, o.violationWeight);
        if (solid[k]) {
            lp.row({{d[k], 1.0}, {slack, 1.0}}, GLP_LO, 1.0, 0.0);  // reaches the gel dose
            lp.row({{d[k], 1.0}, {dMax, -1.0}}, GLP_UP, 0.0, 0.0);
            lp.row({{d[k], 1.0}, {dMin, -1.0}}, GLP_LO, 0.0, 0.0);
        } else {
            lp.row({{d[k], 1.0}, {slack, -1.0}}, GLP_UP, 0.0, 1.0 - o.margin);
        }
    }
}

}  // namespace vpsim::optimise::detail
