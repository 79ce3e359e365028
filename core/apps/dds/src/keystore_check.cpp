// core/apps/dds/src/keystore_check.cpp: an enclave's files checked with OpenSSL's libcrypto (the
// library Fast DDS's security plugins use) before the participant is created.
#include "keystore_check.hpp"

#include <memory>

#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>

namespace tern::core::ddsi {

namespace fs = std::filesystem;

EnclaveFiles enclave_files(const DdsSecurity& s) {
  const fs::path e = s.keystore / "enclaves" / s.enclave;
  return {e / "identity_ca.cert.pem",    e / "cert.pem",       e / "key.pem",
          e / "permissions_ca.cert.pem", e / "governance.p7s", e / "permissions.p7s"};
}

namespace {

template <class T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const { Free(p); }
};
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using Cert = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Pkcs7 = std::unique_ptr<PKCS7, Deleter<PKCS7, PKCS7_free>>;
using Store = std::unique_ptr<X509_STORE, Deleter<X509_STORE, X509_STORE_free>>;

[[noreturn]] void bad(const fs::path& f, const std::string& what) { throw DdsError("dds.security: " + f.string() + ": " + what); }

Bio open(const fs::path& f) {
  Bio b(BIO_new_file(f.c_str(), "r"));
  if (!b) bad(f, "cannot be read");
  return b;
}

Cert certificate(const fs::path& f) {
  Cert c(PEM_read_bio_X509(open(f).get(), nullptr, nullptr, nullptr));
  if (!c) bad(f, "not a PEM X.509 certificate");
  if (X509_cmp_current_time(X509_get0_notBefore(c.get())) > 0) bad(f, "not valid yet");
  if (X509_cmp_current_time(X509_get0_notAfter(c.get())) < 0) bad(f, "expired");
  return c;
}

/// The S/MIME document `f` verifies with the CA certificate `ca`.
void check_signed(const fs::path& f, X509* ca, const fs::path& ca_file) {
  BIO* content = nullptr;
  Pkcs7 p7(SMIME_read_PKCS7(open(f).get(), &content));
  Bio content_owner(content);
  if (!p7) bad(f, "not an S/MIME signed document");
  Store store(X509_STORE_new());
  X509_STORE_add_cert(store.get(), ca);
  Bio out(BIO_new(BIO_s_null()));
  if (PKCS7_verify(p7.get(), nullptr, store.get(), content, out.get(), PKCS7_TEXT) != 1)
    bad(f, "its signature does not verify with " + ca_file.string());
}

void check_present(const DdsSecurity& s, const EnclaveFiles& f) {
  if (!fs::is_directory(s.keystore))
    throw DdsError("dds.security: keystore " + s.keystore.string() + " does not exist (make it with `tern dds keystore create DIR`)");
  for (const auto* p : {&f.identity_ca, &f.certificate, &f.private_key, &f.permissions_ca, &f.governance, &f.permissions})
    if (!fs::exists(*p))
      throw DdsError("dds.security: missing " + p->string() + " (make enclave '" + s.enclave + "' with `tern dds keystore add-node " +
                     s.keystore.string() + " " + s.enclave + "`)");
}

}  // namespace

void check_enclave(const DdsSecurity& s, const EnclaveFiles& f) {
  check_present(s, f);
  const Cert identity_ca = certificate(f.identity_ca);
  const Cert cert = certificate(f.certificate);
  const Cert permissions_ca = certificate(f.permissions_ca);
  const Key key(PEM_read_bio_PrivateKey(open(f.private_key).get(), nullptr, nullptr, const_cast<char*>("")));
  if (!key) bad(f.private_key, "not an unencrypted PEM private key");
  if (X509_check_private_key(cert.get(), key.get()) != 1) bad(f.private_key, "not the key of " + f.certificate.string());
  if (X509_verify(cert.get(), X509_get0_pubkey(identity_ca.get())) != 1) bad(f.certificate, "not signed by " + f.identity_ca.string());
  check_signed(f.governance, permissions_ca.get(), f.permissions_ca);
  check_signed(f.permissions, permissions_ca.get(), f.permissions_ca);
}

}  // namespace tern::core::ddsi
