// The tokens slurmrestd accepts (auth/jwt): HS256 JSON Web Tokens signed with the cluster's key, so that
// granulabd, given the key file, mints its own short-lived tokens instead of holding a long-lived one.
#pragma once

#include <cstdint>
#include <string>

namespace granulab::server::slurm {

/// RFC 4648 base64url without padding (JWT's encoding).
std::string base64url(const std::string& bytes);

/// HS256 token with the claims slurmrestd reads: `sun` (the Slurm user), `iat` = now and `exp` = now +
/// lifespan (Unix seconds), signed with `key` (the bytes of the key file).
std::string slurm_jwt(const std::string& key, const std::string& user, std::int64_t now, int lifespan_seconds);

}  // namespace granulab::server::slurm
