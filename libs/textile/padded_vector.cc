#include "libs/textile/padded_vector.h"

#include "libs/base/demand.h"

namespace haptex::textile {

void PaddedVector::SetRows(const Eigen::VectorXd& x) {
  HAPTEX_DEMAND(x.size() == 3 * rows());
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    for (int i = 0; i < 3; ++i) rows_[r].v[i] = x[static_cast<Eigen::Index>(3 * r) + i];
    rows_[r].v[3] = 0.0;
  }
}

void PaddedVector::AddRowsTo(Eigen::VectorXd* y) const {
  HAPTEX_DEMAND(y->size() == 3 * rows());
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    for (int i = 0; i < 3; ++i) (*y)[static_cast<Eigen::Index>(3 * r) + i] += rows_[r].v[i];
  }
}

Eigen::VectorXd PaddedVector::Rows() const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * rows());
  AddRowsTo(&y);
  return y;
}

}  // namespace haptex::textile
