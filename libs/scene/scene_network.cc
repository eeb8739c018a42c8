#include "libs/scene/scene_network.h"

#include <cctype>
#include <stdexcept>
#include <utility>

#include "libs/netsim/gilbert_elliott.h"
#include "libs/netsim/parameter_check.h"

namespace haptex::scene {
namespace {

using P = v1::ServicePlacement;
using C = netsim::ImpairmentConfig;
using Path = std::vector<std::string>;

constexpr double kMaxRtt_ms = 2 * C::kMaxDelay_ms;

// The pairs that exchange datagrams, and what they carry (for messages). The launcher's table
// (launch/service_table.cc) must agree: tests/launch/service_set_test.cc checks it.
struct Talk {
  ServiceKind x, y;
  const char* carries;
};
constexpr Talk kTalks[] = {
    {P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT, "FingerStates, ForceModels"},
    {P::SERVICE_DEVICE_BRIDGE, P::SERVICE_GLOBAL_SIM, "FingerStates"},
    {P::SERVICE_GLOBAL_SIM, P::SERVICE_LOCAL_CONTACT, "LocalPatch, PatchResult"},
    {P::SERVICE_LOCAL_CONTACT, P::SERVICE_TACTILE, "TouchTrace"},
    {P::SERVICE_TACTILE, P::SERVICE_MOCK_PINS, "PinFrame"},
    {P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB, "the GRAB protocol"},
    {P::SERVICE_DEVICE_BRIDGE, P::SERVICE_VIEWER, "FingerStates and Health for the viewer"},
    {P::SERVICE_LOCAL_CONTACT, P::SERVICE_VIEWER, "ForceModels, TouchTraces and Health for the viewer"},
    {P::SERVICE_GLOBAL_SIM, P::SERVICE_VIEWER, "ClothFrames and Health for the viewer"},
    {P::SERVICE_TACTILE, P::SERVICE_VIEWER, "PinFrames and Health for the viewer"},
};

std::string Dotted(const Path& field) {
  std::string name;
  for (const std::string& part : field) name += (name.empty() ? "" : ".") + part;
  return name;
}

// Runs a netsim check under the field's dotted name; a refusal becomes an issue at that field.
template <typename Check>
void Expect(Path field, Check check, std::vector<LinkIssue>* issues) {
  try {
    check(Dotted(field));
  } catch (const std::invalid_argument& e) {
    issues->push_back({std::move(field), e.what()});
  }
}

Path With(const Path& prefix, const char* field) {
  Path path = prefix;
  path.emplace_back(field);
  return path;
}

void Probability(const Path& prefix, const char* field, double value, std::vector<LinkIssue>* issues) {
  Expect(
      With(prefix, field), [&](const std::string& name) { netsim::CheckProbability(name, value); }, issues);
}

void Range(const Path& prefix, const char* field, double value, double max, std::vector<LinkIssue>* issues) {
  Expect(
      With(prefix, field), [&](const std::string& name) { netsim::CheckRange(name, value, 0.0, max); }, issues);
}

void Distribution(const Path& prefix, const std::string& word, std::vector<LinkIssue>* issues) {
  Expect(
      With(prefix, "jitter_distribution"),
      [&](const std::string& name) {
        try {
          netsim::ParseJitterDistribution(word);
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument(name + ": " + e.what());
        }
      },
      issues);
}

netsim::GilbertElliottConfig BurstConfig(const v1::BurstLoss& burst) {
  netsim::GilbertElliottConfig config;
  config.p_good_to_bad = burst.p();
  config.p_bad_to_good = burst.r();
  config.loss_bad = burst.has_loss_bad() ? burst.loss_bad() : 1.0;
  config.loss_good = burst.loss_good();
  return config;
}

void CheckBurst(const Path& prefix, const v1::BurstLoss& burst, std::vector<LinkIssue>* issues) {
  const std::size_t before = issues->size();
  Probability(prefix, "p", burst.p(), issues);
  Probability(prefix, "r", burst.r(), issues);
  if (burst.has_loss_bad()) Probability(prefix, "loss_bad", burst.loss_bad(), issues);
  Probability(prefix, "loss_good", burst.loss_good(), issues);
  if (issues->size() != before) return;
  // each value is fine: what is left is the chain as a whole (a bad state that never ends)
  Expect(
      With(prefix, "r"),
      [&](const std::string&) { netsim::ValidateGilbertElliott(BurstConfig(burst), (Dotted(prefix) + ".").c_str()); },
      issues);
}

void CheckDirection(const char* direction, const v1::LinkDirection& d, std::vector<LinkIssue>* issues) {
  const Path at = {direction};
  if (d.has_delay_ms()) Range(at, "delay_ms", d.delay_ms(), C::kMaxDelay_ms, issues);
  if (d.has_jitter_ms()) Range(at, "jitter_ms", d.jitter_ms(), C::kMaxDelay_ms, issues);
  if (d.has_jitter_distribution()) Distribution(at, d.jitter_distribution(), issues);
  if (d.has_loss()) Probability(at, "loss", d.loss(), issues);
  if (d.has_burst_loss()) CheckBurst(With(at, "burst_loss"), d.burst_loss(), issues);
  if (d.has_reorder()) Probability(at, "reorder", d.reorder(), issues);
  if (d.has_reorder_delay_ms()) Range(at, "reorder_delay_ms", d.reorder_delay_ms(), C::kMaxDelay_ms, issues);
  if (d.has_duplicate()) Probability(at, "duplicate", d.duplicate(), issues);
  if (d.has_rate_kbps()) Range(at, "rate_kbps", d.rate_kbps(), C::kMaxRate_kbps, issues);
  if (d.has_outage_after_s()) Range(at, "outage_after_s", d.outage_after_s(), C::kMaxOutage_s, issues);
  if (d.has_outage_s()) Range(at, "outage_s", d.outage_s(), C::kMaxOutage_s, issues);
}

// Where an issue's field was written: the path walked down the link's nested messages.
TextIssue Locate(FieldLocator at, const v1::LinkImpairment& link, const LinkIssue& issue) {
  if (issue.field.empty()) return at.Here(issue.message);
  const google::protobuf::Message* message = &link;
  for (std::size_t i = 0; i + 1 < issue.field.size(); ++i) {
    const auto* field = message->GetDescriptor()->FindFieldByName(issue.field[i]);
    if (field == nullptr || field->message_type() == nullptr) return at.Here(issue.message);
    at = at.Nested(*message, issue.field[i]);
    message = &message->GetReflection()->GetMessage(*message, field);
  }
  return at.At(*message, issue.field.back(), -1, issue.message);
}

void ApplyDirection(const v1::LinkDirection& d, netsim::ImpairmentConfig* config, std::uint64_t* seed) {
  if (d.has_delay_ms()) config->delay_ms = d.delay_ms();
  if (d.has_jitter_ms()) config->jitter_ms = d.jitter_ms();
  if (d.has_jitter_distribution())
    config->jitter_distribution = netsim::ParseJitterDistribution(d.jitter_distribution());
  if (d.has_loss()) config->loss = d.loss();
  if (d.has_burst_loss()) config->burst = BurstConfig(d.burst_loss());
  if (d.has_reorder()) config->reorder = d.reorder();
  if (d.has_reorder_delay_ms()) config->reorder_delay_ms = d.reorder_delay_ms();
  if (d.has_duplicate()) config->duplicate = d.duplicate();
  if (d.has_rate_kbps()) config->rate_kbps = d.rate_kbps();
  if (d.has_outage_after_s()) config->outage_after_s = d.outage_after_s();
  if (d.has_outage_s()) config->outage_s = d.outage_s();
  if (d.has_seed()) *seed = d.seed();
}

}  // namespace

std::string ServiceName(ServiceKind kind) {
  std::string name = P::Service_Name(kind);
  if (name.rfind("SERVICE_", 0) != 0) return "service " + std::to_string(static_cast<int>(kind));
  name.erase(0, 8);
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

std::string LinkName(const v1::LinkImpairment& link) { return ServiceName(link.a()) + "-" + ServiceName(link.b()); }

std::string NotRunBecause(const v1::Scene& scene, ServiceKind kind) {
  const bool fingers = scene.fingers_size() > 0;
  switch (kind) {
    case P::SERVICE_GLOBAL_SIM:
      return "";
    case P::SERVICE_LOCAL_CONTACT:
    case P::SERVICE_DEVICE_BRIDGE:
      return fingers ? "" : "the scene has no fingers";
    case P::SERVICE_MOCK_GRAB:
      if (!fingers) return "the scene has no fingers";
      return scene.device().has_mock() ? "" : "the device is a real GRAB controller";
    case P::SERVICE_TACTILE:
      return scene.tactile().enabled() ? "" : "tactile display off";
    case P::SERVICE_MOCK_PINS:
      if (!scene.tactile().enabled()) return "tactile display off";
      return scene.tactile().mock_display() ? "" : "the pin display is a real one";
    case P::SERVICE_VIEWER:
      return scene.viewer().enabled() ? "" : "viewer off";
    default:
      return "not a service";
  }
}

bool SceneRunsService(const v1::Scene& scene, ServiceKind kind) { return NotRunBecause(scene, kind).empty(); }

bool ExchangeDatagrams(ServiceKind x, ServiceKind y) {
  for (const Talk& talk : kTalks) {
    if ((talk.x == x && talk.y == y) || (talk.x == y && talk.y == x)) return true;
  }
  return false;
}

bool SamePair(const v1::LinkImpairment& x, const v1::LinkImpairment& y) {
  return (x.a() == y.a() && x.b() == y.b()) || (x.a() == y.b() && x.b() == y.a());
}

std::vector<LinkIssue> CheckLinkValues(const v1::LinkImpairment& link) {
  std::vector<LinkIssue> issues;
  const Path at;
  Range(at, "rtt_ms", link.rtt_ms(), kMaxRtt_ms, &issues);
  Range(at, "delay_ms", link.delay_ms(), C::kMaxDelay_ms, &issues);
  Range(at, "jitter_ms", link.jitter_ms(), C::kMaxDelay_ms, &issues);
  if (!link.jitter_distribution().empty()) Distribution(at, link.jitter_distribution(), &issues);
  Probability(at, "loss", link.loss(), &issues);
  if (link.has_burst_loss()) CheckBurst({"burst_loss"}, link.burst_loss(), &issues);
  Probability(at, "reorder", link.reorder(), &issues);
  if (link.has_reorder_delay_ms()) Range(at, "reorder_delay_ms", link.reorder_delay_ms(), C::kMaxDelay_ms, &issues);
  Probability(at, "duplicate", link.duplicate(), &issues);
  Range(at, "rate_kbps", link.rate_kbps(), C::kMaxRate_kbps, &issues);
  Range(at, "outage_after_s", link.outage_after_s(), C::kMaxOutage_s, &issues);
  Range(at, "outage_s", link.outage_s(), C::kMaxOutage_s, &issues);
  CheckDirection("forward", link.forward(), &issues);
  CheckDirection("back", link.back(), &issues);
  if (link.rtt_ms() != 0.0 && (link.delay_ms() != 0.0 || link.forward().has_delay_ms() || link.back().has_delay_ms())) {
    issues.push_back({{"rtt_ms"}, "rtt_ms (half each way) and delay_ms say the same thing twice: give one of them"});
  }
  return issues;
}

std::vector<LinkIssue> CheckLinkServices(const v1::LinkImpairment& link, const v1::Scene& scene) {
  std::vector<LinkIssue> issues;
  const auto end_ok = [&](const char* field, ServiceKind kind) {
    if (kind == P::SERVICE_UNSPECIFIED) {
      issues.push_back({{field}, std::string("a link needs both ends: `") + field + ": SERVICE_...`"});
      return false;
    }
    if (kind == P::SERVICE_LAUNCHER || !P::Service_IsValid(kind)) {
      issues.push_back({{field}, ServiceName(kind) + " is not a service a link can join"});
      return false;
    }
    const std::string why = NotRunBecause(scene, kind);
    if (!why.empty()) {
      issues.push_back({{field}, "the scene does not run " + ServiceName(kind) + " (" + why + ")"});
      return false;
    }
    return true;
  };
  const bool a_ok = end_ok("a", link.a());
  const bool b_ok = end_ok("b", link.b());
  if (!a_ok || !b_ok) return issues;
  if (link.a() == link.b()) {
    issues.push_back({{"b"}, "a link joins two different services, got " + ServiceName(link.a()) + " twice"});
  } else if (!ExchangeDatagrams(link.a(), link.b())) {
    std::string pairs;
    for (const Talk& talk : kTalks) {
      pairs +=
          (pairs.empty() ? "" : ", ") + ServiceName(talk.x) + "-" + ServiceName(talk.y) + " (" + talk.carries + ")";
    }
    issues.push_back({{"b"},
                      ServiceName(link.a()) + " and " + ServiceName(link.b()) +
                          " exchange no datagrams; links that carry some: " + pairs});
  }
  return issues;
}

std::vector<TextIssue> ValidateNetwork(const v1::Scene& scene, const FieldLocator& where) {
  std::vector<TextIssue> issues;
  const v1::NetworkSpec& network = scene.network();
  const FieldLocator network_at = where.Nested(scene, "network");
  for (int i = 0; i < network.links_size(); ++i) {
    const v1::LinkImpairment& link = network.links(i);
    const FieldLocator at = network_at.Nested(network, "links", i);
    const std::vector<LinkIssue> ends = CheckLinkServices(link, scene);
    for (const LinkIssue& issue : ends) issues.push_back(Locate(at, link, issue));
    for (const LinkIssue& issue : CheckLinkValues(link)) issues.push_back(Locate(at, link, issue));
    if (!ends.empty()) continue;
    for (int j = 0; j < i; ++j) {
      if (SamePair(network.links(j), link)) {
        const int first_line = network_at.Nested(network, "links", j).Here("").line;
        issues.push_back(at.At(link, "a", -1,
                               "link " + LinkName(link) + " is given twice (first on line " +
                                   std::to_string(first_line) + "): one link per pair of services"));
        break;
      }
    }
  }
  return issues;
}

LinkDirections ResolveLink(const v1::LinkImpairment& link) {
  const std::vector<LinkIssue> issues = CheckLinkValues(link);
  if (!issues.empty()) throw std::invalid_argument("link " + LinkName(link) + ": " + issues.front().message);
  netsim::ImpairmentConfig both;
  both.delay_ms = link.rtt_ms() != 0.0 ? link.rtt_ms() / 2 : link.delay_ms();
  both.jitter_ms = link.jitter_ms();
  if (!link.jitter_distribution().empty()) {
    both.jitter_distribution = netsim::ParseJitterDistribution(link.jitter_distribution());
  }
  both.loss = link.loss();
  if (link.has_burst_loss()) both.burst = BurstConfig(link.burst_loss());
  both.reorder = link.reorder();
  if (link.has_reorder_delay_ms()) both.reorder_delay_ms = link.reorder_delay_ms();
  both.duplicate = link.duplicate();
  both.rate_kbps = link.rate_kbps();
  both.outage_after_s = link.outage_after_s();
  both.outage_s = link.outage_s();
  LinkDirections directions;
  directions.forward = directions.back = both;
  directions.forward_seed = link.has_seed() ? link.seed() : 1;
  directions.back_seed = directions.forward_seed + 1;  // as `haptex relay --seed S` does
  ApplyDirection(link.forward(), &directions.forward, &directions.forward_seed);
  ApplyDirection(link.back(), &directions.back, &directions.back_seed);
  netsim::Validate(directions.forward);
  netsim::Validate(directions.back);
  return directions;
}

}  // namespace haptex::scene
