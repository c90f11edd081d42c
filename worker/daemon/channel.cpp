#include "daemon/channel.h"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/client_interceptor.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "contract/rules.h"
#include "daemon/coordinator_address.h"
#include "util/read_file.h"

namespace farm {
namespace {

namespace exp = grpc::experimental;

// Adds "authorization: Bearer TOKEN" to the initial metadata of a call.
class BearerInterceptor final : public exp::Interceptor {
 public:
  explicit BearerInterceptor(std::string value) : value_(std::move(value)) {}

  void Intercept(exp::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(exp::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA)) {
      methods->GetSendInitialMetadata()->emplace("authorization", value_);
    }
    methods->Proceed();
  }

 private:
  const std::string value_;
};

class BearerInterceptorFactory final : public exp::ClientInterceptorFactoryInterface {
 public:
  explicit BearerInterceptorFactory(const std::string& token) : value_("Bearer " + token) {}

  exp::Interceptor* CreateClientInterceptor(exp::ClientRpcInfo*) override {
    // gRPC takes ownership of the returned interceptor and deletes it when the call ends.
    return std::make_unique<BearerInterceptor>(value_).release();
  }

 private:
  const std::string value_;
};

std::string ReadCaFile(const std::filesystem::path& path) {
  std::string text;
  try {
    text = ReadFile(path);
  } catch (const std::runtime_error&) {
    throw std::runtime_error("cannot read the TLS CA file " + path.string());
  }
  if (text.find("-----BEGIN CERTIFICATE-----") == std::string::npos) {
    throw std::runtime_error("the TLS CA file " + path.string() + " holds no PEM certificate");
  }
  return text;
}

}  // namespace

std::shared_ptr<grpc::Channel> MakeCoordinatorChannel(const WorkerOptions& options) {
  grpc::ChannelArguments args;
  // The contract's largest message either way (a composite task lists every tile).
  args.SetMaxReceiveMessageSize(static_cast<int>(contract::RpcLimits().max_message_bytes()));
  // Notice a restarted coordinator within seconds (gRPC's default backoff grows to 2 min).
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 500);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 5000);
  // Every replica serves every call (their state is in Redis): spread the calls over the
  // ones that answer, and leave out one that went away until it answers again.
  args.SetLoadBalancingPolicyName("round_robin");
  const std::string target = CoordinatorTarget(options.coordinators);
  // One authority for every connection of a list, the first replica's: with TLS the
  // replicas' certificate must name it (gRPC checks each connection against it).
  if (options.coordinators.size() > 1) args.SetString(GRPC_ARG_DEFAULT_AUTHORITY, options.coordinators.front());

  std::shared_ptr<grpc::ChannelCredentials> creds;
  if (options.tls_ca.empty()) {
    creds = grpc::InsecureChannelCredentials();
  } else {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = ReadCaFile(options.tls_ca);
    creds = grpc::SslCredentials(ssl);
  }
  if (options.token.empty()) {
    return grpc::CreateCustomChannel(target, creds, args);
  }
  std::vector<std::unique_ptr<exp::ClientInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(std::make_unique<BearerInterceptorFactory>(options.token));
  return exp::CreateCustomChannelWithInterceptors(target, creds, args,
                                                  std::move(interceptors));
}

}  // namespace farm
