// Status: the result of an operation that can fail on bad user input (a file,
// an option, data that cannot be reconstructed). Programmer errors are CHECKs;
// everything a user can cause is a Status with a message that names the file,
// variable or value at fault.
#ifndef NRSFM_CORE_MODEL_STATUS_H_
#define NRSFM_CORE_MODEL_STATUS_H_

#include <string>
#include <utility>

namespace nrsfm {

class Status {
 public:
  Status() = default;  // OK.
  static Status OK() { return Status(); }
  static Status Error(std::string message) {
    Status status;
    status.ok_ = false;
    status.message_ = std::move(message);
    return status;
  }

  bool ok() const { return ok_; }
  // Empty when ok().
  const std::string& message() const { return message_; }

  // Returns a copy whose message is "<context>: <message>" (unchanged if ok).
  Status WithContext(const std::string& context) const {
    if (ok_) return *this;
    return Error(context + ": " + message_);
  }

 private:
  bool ok_ = true;
  std::string message_;
};

}  // namespace nrsfm

// Returns early from the calling function if `expr` yields a non-OK Status.
#define NRSFM_RETURN_IF_ERROR(expr)                \
  do {                                             \
    ::nrsfm::Status _nrsfm_status = (expr);        \
    if (!_nrsfm_status.ok()) return _nrsfm_status; \
  } while (false)

#endif  // NRSFM_CORE_MODEL_STATUS_H_
