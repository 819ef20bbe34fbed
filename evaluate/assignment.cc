#include "evaluate/assignment.h"

#include <limits>

namespace lsds::evaluate {

namespace {

// The Hungarian method with potentials for n <= m (rows <= cols), O(n^2 m):
// rows are added one at a time, each along a shortest augmenting path.
std::vector<int> AssignRows(const std::vector<double>& cost, size_t n, size_t m) {
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based; column 0 is the virtual start of each augmenting path.
  std::vector<double> u(n + 1, 0), v(m + 1, 0);
  std::vector<size_t> row_of(m + 1, 0), way(m + 1, 0);
  for (size_t i = 1; i <= n; ++i) {
    row_of[0] = i;
    size_t j0 = 0;
    std::vector<double> least(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const size_t i0 = row_of[j0];
      double delta = inf;
      size_t j1 = 0;
      for (size_t j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double reduced = cost[(i0 - 1) * m + (j - 1)] - u[i0] - v[j];
        if (reduced < least[j]) least[j] = reduced, way[j] = j0;
        if (least[j] < delta) delta = least[j], j1 = j;
      }
      for (size_t j = 0; j <= m; ++j) {
        if (used[j]) {
          u[row_of[j]] += delta;
          v[j] -= delta;
        } else {
          least[j] -= delta;
        }
      }
      j0 = j1;
    } while (row_of[j0] != 0);
    do {
      const size_t j1 = way[j0];
      row_of[j0] = row_of[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> column_of(n, -1);
  for (size_t j = 1; j <= m; ++j)
    if (row_of[j] != 0) column_of[row_of[j] - 1] = static_cast<int>(j - 1);
  return column_of;
}

}  // namespace

std::vector<int> MinCostAssignment(const std::vector<double>& cost, size_t rows, size_t cols) {
  if (rows == 0 || cols == 0) return std::vector<int>(rows, -1);
  if (rows <= cols) return AssignRows(cost, rows, cols);
  // More rows than columns: assign the columns to rows, then invert.
  std::vector<double> transposed(cost.size());
  for (size_t r = 0; r < rows; ++r)
    for (size_t c = 0; c < cols; ++c) transposed[c * rows + r] = cost[r * cols + c];
  const std::vector<int> row_of_column = AssignRows(transposed, cols, rows);
  std::vector<int> column_of(rows, -1);
  for (size_t c = 0; c < cols; ++c)
    if (row_of_column[c] >= 0)
      column_of[static_cast<size_t>(row_of_column[c])] = static_cast<int>(c);
  return column_of;
}

}  // namespace lsds::evaluate
