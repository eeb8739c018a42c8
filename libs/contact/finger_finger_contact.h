#pragma once
// States II/III (paper 5.2): the fingers touch each other with no fabric between. The index
// finger is observed in the thumb's frame; a proxy on the thumb's surface holds the touching
// point; a linear normal spring (1.25 N/mm) and a tangential spring with Coulomb stick-slip give
// the force, equal and opposite on the two fingers.

#include <Eigen/Core>

#include "libs/contact/contact_options.h"
#include "libs/contact/finger_geometry.h"

namespace haptex::contact {

struct FingerFingerResult {
  bool touching = false;
  bool sliding = false;
  double penetration_m = 0.0;
  double normal_N = 0.0;
  double tangential_N = 0.0;
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};                  ///< from the thumb towards the index
  Eigen::Vector3d force_on_index_W_N{Eigen::Vector3d::Zero()};         ///< the thumb gets the opposite
  Eigen::Matrix3d stiffness_index_W_N_per_m{Eigen::Matrix3d::Zero()};  ///< d F_index / d x_index
};

class FingerFingerContact {
 public:
  explicit FingerFingerContact(const ContactOptions& options);

  /// `gap_offset_m` widens the touching distance (twice the fabric half thickness when the fabric
  /// is squeezed between the fingers, as in VIII/IX).
  FingerFingerResult Update(const FingerPose& thumb, const FingerPose& index, double gap_offset_m,
                            const FrictionCoefficients& mu, bool with_friction);
  void Reset();
  /// Gap between the finger surfaces (negative: they overlap) and the unit normal thumb -> index.
  static double Gap(const ContactOptions& options, const FingerPose& thumb, const FingerPose& index,
                    Eigen::Vector3d* normal_W, Eigen::Vector3d* closest_thumb_W, Eigen::Vector3d* closest_index_W);

 private:
  ContactOptions options_;
  bool touching_ = false;
  bool sliding_ = false;
  Eigen::Vector3d held_thumb_F_{Eigen::Vector3d::Zero()};  ///< proxy on the thumb, thumb frame
};

}  // namespace haptex::contact
