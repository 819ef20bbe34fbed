// The optimal assignment of rows to columns, as scipy.optimize's
// linear_sum_assignment gives it (TrackEval matches tracker boxes to ground
// truth with it): min(rows, cols) pairs of the least total cost.
#pragma once

#include <cstddef>
#include <vector>

namespace lsds::evaluate {

// `cost` is rows x cols, row-major, finite. Returns per row its column, or -1
// for a row left without one (rows > cols). Of several optimal assignments
// one is returned (scipy may return another).
std::vector<int> MinCostAssignment(const std::vector<double>& cost, size_t rows, size_t cols);

}  // namespace lsds::evaluate
