#include "hymm/datasets/MatFile.h"

#include <matio.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>

#include "mat_checker.h"

namespace hymm::datasets
{
namespace
{
mat_t* asMat(void* p) { return static_cast<mat_t*>(p); }

struct VarDeleter
{
    void operator()(matvar_t* v) const { Mat_VarFree(v); }
};
using VarPtr = std::unique_ptr<matvar_t, VarDeleter>;

template <typename T>
void copyAs(const void* data, Eigen::MatrixXd& out)
{
    const T* src = static_cast<const T*>(data);
    for (Eigen::Index i = 0; i < out.size(); ++i) out.data()[i] = static_cast<double>(src[i]);
}

std::runtime_error varError(const std::string& path, const std::string& name,
                            const std::string& what)
{
    return std::runtime_error("MAT file '" + path + "', variable '" + name + "': " + what);
}

}  // namespace

MatFile::MatFile(const std::string& path) : path_(path)
{
    {
        std::ifstream in(path, std::ios::binary);
        if (!in)
            throw std::runtime_error("cannot open MAT file '" + path + "' (missing or unreadable)");
        const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
        detail::MatChecker(path, bytes.size()).check(bytes);
    }
    mat_ = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
    if (!mat_)
        throw std::runtime_error(
            "cannot open MAT file '" + path + "' (missing, unreadable or not a MAT file)");
}

MatFile::~MatFile()
{
    if (mat_) Mat_Close(asMat(mat_));
}

std::vector<std::string> MatFile::variableNames() const
{
    std::vector<std::string> names;
    Mat_Rewind(asMat(mat_));
    while (matvar_t* v = Mat_VarReadNextInfo(asMat(mat_)))
    {
        if (v->name) names.emplace_back(v->name);
        Mat_VarFree(v);
    }
    Mat_Rewind(asMat(mat_));
    return names;
}

bool MatFile::hasVariable(const std::string& name) const
{
    VarPtr v(Mat_VarReadInfo(asMat(mat_), name.c_str()));
    return v != nullptr;
}

Eigen::MatrixXd MatFile::readMatrix(const std::string& name) const
{
    VarPtr v(Mat_VarRead(asMat(mat_), name.c_str()));
    if (!v) throw varError(path_, name, "not found or unreadable");
    if (v->isComplex) throw varError(path_, name, "complex data is not supported");
    if (v->rank != 2) throw varError(path_, name, "expected a 2-D matrix");
    const auto rows = static_cast<Eigen::Index>(v->dims[0]);
    const auto cols = static_cast<Eigen::Index>(v->dims[1]);
    Eigen::MatrixXd m(rows, cols);
    if (m.size() == 0) return m;
    if (!v->data) throw varError(path_, name, "no data");
    switch (v->class_type)
    {  // MATLAB stores column-major, like Eigen's default
        case MAT_C_DOUBLE: copyAs<double>(v->data, m); break;
        case MAT_C_SINGLE: copyAs<float>(v->data, m); break;
        case MAT_C_INT8: copyAs<int8_t>(v->data, m); break;
        case MAT_C_UINT8: copyAs<uint8_t>(v->data, m); break;
        case MAT_C_INT16: copyAs<int16_t>(v->data, m); break;
        case MAT_C_UINT16: copyAs<uint16_t>(v->data, m); break;
        case MAT_C_INT32: copyAs<int32_t>(v->data, m); break;
        case MAT_C_UINT32: copyAs<uint32_t>(v->data, m); break;
        case MAT_C_INT64: copyAs<int64_t>(v->data, m); break;
        case MAT_C_UINT64: copyAs<uint64_t>(v->data, m); break;
        default:
            throw varError(path_, name,
                           "class " + std::to_string(static_cast<int>(v->class_type)) +
                               " is not a real numeric matrix");
    }
    return m;
}

Eigen::VectorXd MatFile::readVector(const std::string& name) const
{
    const Eigen::MatrixXd m = readMatrix(name);
    if (m.rows() != 1 && m.cols() != 1 && m.size() != 0)
        throw varError(path_, name,
                       "expected a vector, got " + std::to_string(m.rows()) + "x" +
                           std::to_string(m.cols()));
    return Eigen::Map<const Eigen::VectorXd>(m.data(), m.size());
}

void writeMatFile(
    const std::string& path, const std::vector<std::pair<std::string, Eigen::MatrixXd>>& vars)
{
    mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, MAT_FT_MAT5);
    if (!mat) throw std::runtime_error("cannot create MAT file '" + path + "'");
    for (const auto& [name, value] : vars)
    {
        Eigen::MatrixXd copy = value;  // matio takes a non-const pointer
        size_t dims[2] = {static_cast<size_t>(copy.rows()), static_cast<size_t>(copy.cols())};
        matvar_t* v = Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                                    copy.data(), 0);
        const bool ok = v && Mat_VarWrite(mat, v, MAT_COMPRESSION_NONE) == 0;
        if (v) Mat_VarFree(v);
        if (!ok)
        {
            Mat_Close(mat);
            throw std::runtime_error("cannot write variable '" + name + "' to '" + path + "'");
        }
    }
    if (Mat_Close(mat) != 0) throw std::runtime_error("error closing MAT file '" + path + "'");
}

}  // namespace hymm::datasets
