// core/apps/dds/src/keystore.cpp: `tern dds keystore create|add-node` (dds_keystore.hpp) with Debian's
// openssl command: EC prime256v1 keys, a self-signed CA, certificates and S/MIME signatures.
#include <cctype>
#include <ctime>
#include <fstream>
#include <random>

#include <fmt/format.h>

#include "dds_bridge.hpp"
#include "dds_keystore.hpp"
#include "keystore_documents.hpp"
#include "openssl_command.hpp"

namespace tern::core {

namespace fs = std::filesystem;
using namespace ddsi;

namespace {

constexpr int kValidDays = 3650;  // CA, identities and permissions: ten years from their making

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
  if (!out.flush()) throw DdsError("cannot write " + p.string());
}

void make_key(const fs::path& key, const fs::path& cwd) {
  run_openssl({"genpkey", "-algorithm", "EC", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-out", key.string()}, cwd);
  fs::permissions(key, fs::perms::owner_read | fs::perms::owner_write);
}

/// S/MIME clear-signed (text, detached) by the permissions CA, as SROS2 signs and Fast DDS reads.
void sign(const fs::path& keystore, const fs::path& xml, const fs::path& p7s) {
  run_openssl({"smime", "-sign", "-text", "-in", xml.string(), "-out", p7s.string(), "-signer",
               (keystore / "public/permissions_ca.cert.pem").string(), "-inkey", (keystore / "private/permissions_ca.key.pem").string()},
              keystore);
}

/// "YYYY-MM-DDThh:mm:ss" (UTC) of now + `days`.
std::string utc(int days) {
  const std::time_t t = std::time(nullptr) + static_cast<std::time_t>(days) * 86400;
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

/// openssl -subj text: '/' inside a value escaped.
std::string subject(const std::string& cn) {
  std::string s = "/CN=";
  for (char c : cn) s += c == '/' ? std::string("\\/") : std::string(1, c);
  return s;
}

std::string random_serial() {
  std::random_device rd;
  return fmt::format("0x{:08x}{:08x}", rd() & 0x7fffffffU, rd());
}

}  // namespace

bool is_enclave_name(const std::string& name) {
  if (name.empty() || name.front() == '/' || name.back() == '/' || name.find("//") != std::string::npos) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/')) return false;
  return true;
}

void create_keystore(const fs::path& dir_in) {
  const fs::path dir = fs::absolute(dir_in).lexically_normal();
  if (fs::exists(dir / "public/ca.cert.pem")) throw DdsError(dir.string() + " already holds a keystore (public/ca.cert.pem)");
  require_openssl();  // before any directory is made
  for (const char* d : {"public", "private", "enclaves"}) fs::create_directories(dir / d);
  fs::permissions(dir / "private", fs::perms::owner_all);
  make_key(dir / "private/ca.key.pem", dir);
  run_openssl({"req", "-new", "-x509", "-sha256", "-days", std::to_string(kValidDays), "-key", "private/ca.key.pem", "-subj",
               "/CN=tern keystore CA", "-addext", "basicConstraints=critical,CA:TRUE", "-addext",
               "keyUsage=critical,digitalSignature,keyCertSign,cRLSign", "-out", "public/ca.cert.pem"},
              dir);
  // digitalSignature: the CA also signs governance and permissions (S/MIME signer purpose)
  // one CA in both roles (identity and permissions), as SROS2's create_keystore
  for (const char* role : {"identity_ca", "permissions_ca"}) {
    fs::copy_file(dir / "public/ca.cert.pem", dir / "public" / (std::string(role) + ".cert.pem"), fs::copy_options::overwrite_existing);
    fs::copy_file(dir / "private/ca.key.pem", dir / "private" / (std::string(role) + ".key.pem"), fs::copy_options::overwrite_existing);
  }
  write_text(dir / "enclaves/governance.xml", governance_xml());
  sign(dir, dir / "enclaves/governance.xml", dir / "enclaves/governance.p7s");
}

void add_keystore_node(const fs::path& dir_in, const std::string& name) {
  const fs::path dir = fs::absolute(dir_in).lexically_normal();
  if (!is_enclave_name(name)) throw DdsError("'" + name + "' is not an enclave name (letters, digits, '_', parts separated by '/')");
  for (const char* f : {"public/identity_ca.cert.pem", "private/identity_ca.key.pem", "enclaves/governance.p7s"})
    if (!fs::exists(dir / f))
      throw DdsError(dir.string() + " is not a keystore (no " + f + "): make one with `tern dds keystore create " + dir_in.string() + "`");
  require_openssl();
  const fs::path e = dir / "enclaves" / name;
  if (fs::exists(e / "cert.pem")) throw DdsError("enclave '" + name + "' exists already: " + (e / "cert.pem").string());
  fs::create_directories(e);
  make_key(e / "key.pem", e);
  run_openssl({"req", "-new", "-sha256", "-key", "key.pem", "-subj", subject(name), "-out", "cert.csr"}, e);
  write_text(e / "cert.ext", "basicConstraints=critical,CA:FALSE\n");
  run_openssl({"x509", "-req", "-sha256", "-days", std::to_string(kValidDays), "-in", "cert.csr", "-CA",
               (dir / "public/identity_ca.cert.pem").string(), "-CAkey", (dir / "private/identity_ca.key.pem").string(), "-set_serial",
               random_serial(), "-extfile", "cert.ext", "-out", "cert.pem"},
              e);
  fs::remove(e / "cert.csr");
  fs::remove(e / "cert.ext");
  for (const char* f : {"identity_ca.cert.pem", "permissions_ca.cert.pem"})
    fs::copy_file(dir / "public" / f, e / f, fs::copy_options::overwrite_existing);
  fs::copy_file(dir / "enclaves/governance.p7s", e / "governance.p7s", fs::copy_options::overwrite_existing);
  write_text(e / "permissions.xml", permissions_xml(name, utc(0), utc(kValidDays)));
  sign(dir, e / "permissions.xml", e / "permissions.p7s");
}

}  // namespace tern::core
