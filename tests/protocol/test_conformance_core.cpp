// The conformance table (conformance.hpp) against the protocol core in this
// process, over the module the firmware image serves: the same cases the TCP and
// RTU runs take, without a transport, so a failure here is the core's.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "conformance.hpp"
#include "fakes.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/modbus/modbus_core.hpp"
#include "module_rig.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/records.hpp"

namespace {

namespace c = trueaxis::conformance;
namespace m = trueaxis::macros;

class CoreTransport final : public c::Transport {
 public:

  bool exchange(const c::Bytes& pdu, c::Bytes& reply, std::string&) override {
    std::uint8_t response[trueaxis::modbus::kMaxPduBytes];
    const std::size_t n = core_.respond(pdu.data(), pdu.size(), response);
    module_.step();
    reply.assign(response, response + n);
    return true;
  }

  m::Module& module() { return module_; }

 private:
  trueaxis::test::ModuleRig rig_;
  m::Module& module_ = rig_.module();
  trueaxis::modbus::ModbusCore core_{module_};
};

}  // namespace

TEST_CASE("the conformance table holds against the protocol core over the module") {
  CoreTransport t;
  const std::vector<c::Case> cases = c::pdu_cases();
  REQUIRE(cases.size() >= 120);
  const c::Outcome out = c::run_cases(t, cases);
  for (const std::string& f : out.failures) UNSCOPED_INFO(f);
  CHECK(out.failures.empty());
  CHECK(out.cases == cases.size());
}

TEST_CASE("the conformance runner catches a wrong reply and a changed variable") {
  // The runner itself, against a transport that lies: it must not pass.
  class Liar final : public c::Transport {
   public:
    bool exchange(const c::Bytes& pdu, c::Bytes& reply, std::string& why) override {
      const bool ok = inner.exchange(pdu, reply, why);
      // From the 60th request on, #9 seems to have changed.
      if (++count >= 60 && pdu == c::fc3(4, 36)) reply.back() ^= 1;
      return ok;
    }
    CoreTransport inner;
    int count = 0;
  };
  Liar t;
  std::vector<c::Case> cases = c::pdu_cases();
  cases.resize(8);
  const c::Outcome out = c::run_cases(t, cases);
  REQUIRE_FALSE(out.failures.empty());
  REQUIRE(out.failures.size() == 1);
  CHECK(out.failures[0].find(": changed #9") != std::string::npos);

  c::Case wrong = c::pdu_cases()[0];
  wrong.reply.back() ^= 1;
  CoreTransport honest;
  CHECK(c::run_cases(honest, {wrong}).failures.size() == 1);
}

TEST_CASE("with the whole state read every 25 cases, the table still holds and a change outside the addressed runs is caught") {
  CoreTransport t;
  const std::vector<c::Case> cases = c::pdu_cases();
  const c::Outcome out = c::run_cases(t, cases, 25);
  for (const std::string& f : out.failures) UNSCOPED_INFO(f);
  CHECK(out.failures.empty());

  // A transport that also writes #26 (read only in the whole state) when it
  // serves function code 65: only the whole read after that case's block sees it.
  class Sneak final : public c::Transport {
   public:
    bool exchange(const c::Bytes& pdu, c::Bytes& reply, std::string& why) override {
      if (pdu[0] == 65) {
        c::Bytes ignored;
        inner.exchange(c::fc16_values(26, {5.0}), ignored, why);
      }
      return inner.exchange(pdu, reply, why);
    }
    CoreTransport inner;
  };
  Sneak s;
  const c::Outcome caught = c::run_cases(s, cases, 25);
  REQUIRE(caught.failures.size() == 1);
  // Three setting cases come first, so function code 65 is case 69, in the
  // block of cases 51..75, which ends with function code 71.
  CHECK(caught.failures[0] == "the 25 cases up to function code 71: changed #26");
}
