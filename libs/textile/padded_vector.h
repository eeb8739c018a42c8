#pragma once
// A vector of 3-component rows stored 4 apart: row r at [4 r, 4 r + 3), with entry 4 r + 3 a
// pad (0 while the rows are finite), and the storage 32-byte aligned. Each row is one aligned 4-wide load or store, and
// a row just written can be read back through store forwarding (a 3-wide masked store cannot be): Gauss-Seidel's sweeps
// run on these.

#include <vector>

#include <Eigen/Core>

namespace haptex::textile {

class PaddedVector {
 public:
  PaddedVector() = default;
  explicit PaddedVector(int rows) : rows_(static_cast<std::size_t>(rows)) {}  // zero

  int rows() const { return static_cast<int>(rows_.size()); }
  double* data() { return rows_.empty() ? nullptr : rows_.front().v; }
  const double* data() const { return rows_.empty() ? nullptr : rows_.front().v; }

  /// All 4 rows() entries, pads included. No kernel reads a pad into a row. Pads hold 0 (up to
  /// sign) while the rows are finite, so sums, dot products and norms over this are the rows';
  /// after a non-finite value a pad may stay non-finite until SetRows/SetRow/SetZero.
  Eigen::Map<Eigen::VectorXd, Eigen::Aligned32> vec() { return {data(), 4 * rows()}; }
  Eigen::Map<const Eigen::VectorXd, Eigen::Aligned32> vec() const { return {data(), 4 * rows()}; }

  Eigen::Map<Eigen::Vector3d> row(int r) { return Eigen::Map<Eigen::Vector3d>(data() + 4 * r); }
  Eigen::Map<const Eigen::Vector3d> row(int r) const { return Eigen::Map<const Eigen::Vector3d>(data() + 4 * r); }

  /// Row r and its pad (0): a pad left non-finite by an earlier non-finite step is cleared.
  void SetRow(int r, const Eigen::Vector3d& x) {
    double* d = data() + 4 * r;
    d[0] = x[0], d[1] = x[1], d[2] = x[2], d[3] = 0.0;
  }
  void SetZero() { vec().setZero(); }
  /// Rows from `x` (3 per row, x.size() == 3 rows()); pads 0.
  void SetRows(const Eigen::VectorXd& x);
  /// y += the rows (y->size() == 3 rows()).
  void AddRowsTo(Eigen::VectorXd* y) const;
  /// The rows, 3 per row. Allocates (for tests and callers outside hot loops).
  Eigen::VectorXd Rows() const;

 private:
  struct alignas(32) Row {
    double v[4] = {0.0, 0.0, 0.0, 0.0};
  };
  std::vector<Row> rows_;
};

}  // namespace haptex::textile
