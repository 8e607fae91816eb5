#include "matlab/mex_util.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>

namespace nrsfm {
namespace mex {

std::string Lower(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string SizeText(const mxArray* a) {
  const mwSize n = mxGetNumberOfDimensions(a);
  const mwSize* dims = mxGetDimensions(a);
  std::string text;
  for (mwSize i = 0; i < n; ++i)
    text += (i ? " x " : "") + std::to_string(dims[i]);
  return text;
}

Status ToMatrix(const mxArray* a, const std::string& name,
                Eigen::MatrixXd* out) {
  if (!(mxIsNumeric(a) || mxIsLogical(a)) || mxIsComplex(a) || mxIsSparse(a) ||
      mxGetNumberOfDimensions(a) != 2) {
    return Status::Error(name +
                         " must be a real full 2-D numeric matrix, got a " +
                         std::string(mxGetClassName(a)) + " array of size " +
                         SizeText(a) + (mxIsSparse(a) ? " (sparse)" : ""));
  }
  const mwSize rows = mxGetM(a), cols = mxGetN(a);
  out->resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  if (mxIsDouble(a)) {
    *out = Eigen::Map<const Eigen::MatrixXd>(mxGetPr(a), rows, cols);
    return Status::OK();
  }
  // Other classes element by element (mxGetScalar reads only the first).
  mxArray* converted = nullptr;
  mxArray* input = const_cast<mxArray*>(a);
  if (mexCallMATLABWithTrap(1, &converted, 1, &input, "double") != nullptr ||
      converted == nullptr) {
    return Status::Error(name + ": cannot convert a " +
                         std::string(mxGetClassName(a)) + " array to double");
  }
  *out = Eigen::Map<const Eigen::MatrixXd>(mxGetPr(converted), rows, cols);
  mxDestroyArray(converted);
  return Status::OK();
}

Status ValueText(const mxArray* a, const std::string& name, std::string* text) {
  if (mxIsChar(a)) {
    char* s = mxArrayToString(a);
    if (s == nullptr) return Status::Error(name + " must be a char row vector");
    *text = s;
    mxFree(s);
    return Status::OK();
  }
  if ((mxIsNumeric(a) || mxIsLogical(a)) && !mxIsComplex(a) &&
      mxGetNumberOfElements(a) == 1) {
    if (mxIsLogical(a)) {
      *text = mxGetLogicals(a)[0] ? "true" : "false";
      return Status::OK();
    }
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.17g", mxGetScalar(a));
    *text = buffer;
    return Status::OK();
  }
  return Status::Error(
      name +
      " must be a char row, or a real numeric or logical scalar; got a " +
      std::string(mxGetClassName(a)) + " array of size " + SizeText(a));
}

std::vector<std::pair<std::string, std::string>> OptionNames(
    const std::vector<tools::FlagRole>& roles) {
  std::vector<std::pair<std::string, std::string>> names;
  for (const tools::FlagInfo& flag : tools::CommandFlagTable()) {
    if (std::find(roles.begin(), roles.end(), flag.role) != roles.end()) {
      names.emplace_back(Lower(flag.name), flag.name);
    }
  }
  return names;
}

Status SetOption(const std::vector<std::pair<std::string, std::string>>& names,
                 const std::string& name, const mxArray* value,
                 const std::string& others, tools::CommandFlags* flags) {
  const std::string lower = Lower(name);
  std::string flag;
  for (const auto& [key, flag_name] : names) {
    if (key == lower) flag = flag_name;
  }
  if (flag.empty()) {
    std::string known = others;
    for (const auto& entry : names) known += ", " + entry.second;
    return Status::Error("unknown option '" + name + "'; the options are " +
                         known);
  }
  std::string text;
  NRSFM_RETURN_IF_ERROR(ValueText(value, flag, &text));
  return tools::SetFlagFromText(flag, text, flags);
}

mxArray* NewArray(std::vector<mwSize> dims) {
  return mxCreateNumericArray(dims.size(), dims.data(), mxDOUBLE_CLASS, mxREAL);
}

std::string ErrorOf(const std::function<Status()>& run) {
  try {
    const Status status = run();
    return status.ok() ? std::string() : status.message();
  } catch (const std::exception& e) {
    return std::string("internal error: ") + e.what();
  }
}

}  // namespace mex
}  // namespace nrsfm
