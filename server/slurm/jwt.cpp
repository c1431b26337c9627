#include "server/slurm/jwt.h"

#include <openssl/evp.h>
#include <openssl/hmac.h>

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace granulab::server::slurm {

std::string base64url(const std::string& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
  std::string out;
  out.reserve((bytes.size() * 4 + 2) / 3);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    for (int k = 18; k >= 0; k -= 6) out += alphabet[(v >> k) & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += alphabet[(v >> 18) & 63], out += alphabet[(v >> 12) & 63];
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += alphabet[(v >> 18) & 63], out += alphabet[(v >> 12) & 63], out += alphabet[(v >> 6) & 63];
  }
  return out;
}

std::string slurm_jwt(const std::string& key, const std::string& user, std::int64_t now, int lifespan_seconds) {
  const std::string header = base64url(R"({"alg":"HS256","typ":"JWT"})");
  const std::string claims =
      base64url(nlohmann::json{{"exp", now + lifespan_seconds}, {"iat", now}, {"sun", user}}.dump());
  const std::string signed_part = header + "." + claims;
  unsigned char mac[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (!HMAC(EVP_sha256(), key.data(), int(key.size()), reinterpret_cast<const unsigned char*>(signed_part.data()),
            signed_part.size(), mac, &length))
    throw std::runtime_error("cannot sign the Slurm token (OpenSSL HMAC failed)");
  return signed_part + "." + base64url(std::string(reinterpret_cast<const char*>(mac), length));
}

}  // namespace granulab::server::slurm
