#include "launch/trace_export.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "libs/codec/message_conversion.h"

namespace haptex::launch {
namespace {

class CsvFiles {
 public:
  explicit CsvFiles(std::string dir) : dir_(std::move(dir)) {}

  std::ofstream& Row(const std::string& name, const char* header) {
    auto& file = files_[name];
    if (!file) {
      file = std::make_unique<std::ofstream>(dir_ + "/" + name);
      if (!*file) throw std::runtime_error("cannot write " + dir_ + "/" + name);
      *file << header << "\n";
      file->precision(9);
    }
    ++rows_[name];
    return *file;
  }
  std::map<std::string, std::size_t> rows() const { return rows_; }

 private:
  std::string dir_;
  std::map<std::string, std::unique_ptr<std::ofstream>> files_;
  std::map<std::string, std::size_t> rows_;
};

double Norm(const v1::Vec3& v) { return std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z()); }

}  // namespace

std::string FingerName(int finger) { return codec::FingerName(static_cast<v1::Finger>(finger)); }

std::map<std::string, std::size_t> ExportCsv(const std::vector<Recording>& recordings, const std::string& out_dir) {
  std::filesystem::create_directories(out_dir);
  CsvFiles csv(out_dir);
  const std::int64_t t0 = EarliestSendTimeNs(recordings);
  for (const Recording& recording : recordings) {
    for (const v1::Envelope& e : recording.envelopes) {
      const double t = static_cast<double>(e.send_time_ns() - t0) * 1e-9;
      const std::string& sender = e.sender();
      switch (e.body_case()) {
        case v1::Envelope::kHealth:
          for (const v1::LoopStats& l : e.health().loops()) {
            csv.Row("health.csv",
                    "t_s,sender,state,uptime_s,loop,target_rate_hz,ticks,overruns,period_p50_us,"
                    "period_p99_us,period_max_us,compute_p50_us,compute_p99_us,compute_max_us")
                << t << ',' << sender << ',' << v1::Health::State_Name(e.health().state()) << ','
                << e.health().uptime_s() << ',' << l.name() << ',' << l.target_rate_hz() << ',' << l.ticks() << ','
                << l.overruns() << ',' << l.period_p50_us() << ',' << l.period_p99_us() << ',' << l.period_max_us()
                << ',' << l.compute_p50_us() << ',' << l.compute_p99_us() << ',' << l.compute_max_us() << '\n';
          }
          for (const v1::Counter& c : e.health().counters()) {
            csv.Row("health_counters.csv", "t_s,sender,counter,value")
                << t << ',' << sender << ',' << c.name() << ',' << c.value() << '\n';
          }
          for (const v1::LatencyStats& l : e.health().latencies()) {
            csv.Row("health_latencies.csv", "t_s,sender,latency,samples,p50_us,p99_us,max_us")
                << t << ',' << sender << ',' << l.name() << ',' << l.samples() << ',' << l.p50_us() << ',' << l.p99_us()
                << ',' << l.max_us() << '\n';
          }
          break;
        case v1::Envelope::kForceModel:
          for (const v1::FingerForceModel& m : e.force_model().fingers()) {
            csv.Row("force_model.csv",
                    "t_s,sender,finger,f0_x_n,f0_y_n,f0_z_n,f0_norm_n,x0_x_m,x0_y_m,x0_z_m,ttl_s,contact_state")
                << t << ',' << sender << ',' << FingerName(m.finger()) << ',' << m.f0_w_n().x() << ',' << m.f0_w_n().y()
                << ',' << m.f0_w_n().z() << ',' << Norm(m.f0_w_n()) << ',' << m.x0_w_m().x() << ',' << m.x0_w_m().y()
                << ',' << m.x0_w_m().z() << ',' << m.ttl_s() << ',' << static_cast<int>(m.contact_state()) << '\n';
          }
          break;
        case v1::Envelope::kTouchTrace:
          for (const v1::FingerTouch& f : e.touch_trace().fingers()) {
            csv.Row("touch_trace.csv",
                    "t_s,sender,finger,in_contact,u_m,v_m,slip_u_m_per_s,slip_v_m_per_s,normal_force_n,finger_angle_"
                    "rad,contact_state")
                << t << ',' << sender << ',' << FingerName(f.finger()) << ',' << (f.in_contact() ? 1 : 0) << ','
                << f.u_m() << ',' << f.v_m() << ',' << f.slip_u_m_per_s() << ',' << f.slip_v_m_per_s() << ','
                << f.normal_force_n() << ',' << f.finger_angle_rad() << ',' << static_cast<int>(f.contact_state())
                << '\n';
          }
          break;
        case v1::Envelope::kFingerStates:
          for (const v1::FingerState& f : e.finger_states().fingers()) {
            csv.Row("finger_states.csv",
                    "t_s,sender,controller_sequence,device_ok,finger,x_m,y_m,z_m,vx_m_per_s,vy_m_per_s,vz_m_per_s,"
                    "force_x_n,force_y_n,force_z_n")
                << t << ',' << sender << ',' << e.finger_states().controller_sequence() << ','
                << (e.finger_states().device_ok() ? 1 : 0) << ',' << FingerName(f.finger()) << ','
                << f.position_w_m().x() << ',' << f.position_w_m().y() << ',' << f.position_w_m().z() << ','
                << f.velocity_w_m_per_s().x() << ',' << f.velocity_w_m_per_s().y() << ',' << f.velocity_w_m_per_s().z()
                << ',' << f.measured_force_w_n().x() << ',' << f.measured_force_w_n().y() << ','
                << f.measured_force_w_n().z() << '\n';
          }
          break;
        case v1::Envelope::kPinFrame:
          for (const v1::FingerPins& p : e.pin_frame().fingers()) {
            double sum40 = 0, sum320 = 0, max40 = 0, max320 = 0;
            for (const float a : p.amplitude_40hz())
              sum40 += static_cast<double>(a), max40 = std::max(max40, static_cast<double>(a));
            for (const float a : p.amplitude_320hz())
              sum320 += static_cast<double>(a), max320 = std::max(max320, static_cast<double>(a));
            const double n40 = std::max(1, p.amplitude_40hz_size()), n320 = std::max(1, p.amplitude_320hz_size());
            csv.Row("pin_frame.csv", "t_s,sender,frame_index,finger,mean_40hz,max_40hz,mean_320hz,max_320hz")
                << t << ',' << sender << ',' << e.pin_frame().frame_index() << ',' << FingerName(p.finger()) << ','
                << sum40 / n40 << ',' << max40 << ',' << sum320 / n320 << ',' << max320 << '\n';
          }
          break;
        case v1::Envelope::kControl:
          csv.Row("control.csv", "t_s,sender,command,target_service,reason")
              << t << ',' << sender << ',' << v1::Control::Command_Name(e.control().command()) << ','
              << e.control().target_service() << ',' << e.control().reason() << '\n';
          break;
        case v1::Envelope::kLocalPatch:
          csv.Row("local_patch.csv", "t_s,sender,bytes")
              << t << ',' << sender << ',' << e.local_patch().ByteSizeLong() << '\n';
          break;
        case v1::Envelope::kPatchResult:
          csv.Row("patch_result.csv", "t_s,sender,bytes")
              << t << ',' << sender << ',' << e.patch_result().ByteSizeLong() << '\n';
          break;
        case v1::Envelope::kClothFrame:
          csv.Row("cloth_frame.csv", "t_s,sender,bytes")
              << t << ',' << sender << ',' << e.cloth_frame().ByteSizeLong() << '\n';
          break;
        default:
          break;
      }
    }
  }
  return csv.rows();
}

}  // namespace haptex::launch
