// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/value.h"

#include <cmath>
#include <sstream>

namespace principled::usd {

struct Value::Storage {
    std::vector<double> numbers;
    std::vector<std::string> strings;
    std::vector<AssetPath> assets;
    Dictionary dict;
};

Value Value::none(std::string typeName, bool isArray, SourceLocation where) {
    Value v;
    v._kind = Kind::None;
    v._typeName = std::move(typeName);
    v._isArray = isArray;
    v._where = std::move(where);
    return v;
}

Value Value::number(std::string typeName, double x, SourceLocation where) {
    Value v;
    v._kind = Kind::Number;
    v._typeName = std::move(typeName);
    v._number = x;
    v._where = std::move(where);
    return v;
}

Value Value::tuple(std::string typeName, std::vector<double> x, SourceLocation where) {
    Value v;
    v._kind = Kind::Tuple;
    v._typeName = std::move(typeName);
    v._components = static_cast<int>(x.size());
    auto s = std::make_shared<Storage>();
    s->numbers = std::move(x);
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::string(std::string typeName, std::string x, SourceLocation where) {
    Value v;
    v._kind = Kind::String;
    v._typeName = std::move(typeName);
    auto s = std::make_shared<Storage>();
    s->strings.push_back(std::move(x));
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::asset(AssetPath a, SourceLocation where) {
    Value v;
    v._kind = Kind::Asset;
    v._typeName = "asset";
    auto s = std::make_shared<Storage>();
    s->strings.push_back(a.authored);
    s->assets.push_back(std::move(a));
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::path(std::string p, SourceLocation where) {
    Value v;
    v._kind = Kind::Path;
    v._typeName = "path";
    auto s = std::make_shared<Storage>();
    s->strings.push_back(std::move(p));
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::numberArray(std::string typeName, int components, std::vector<double> x,
                         SourceLocation where) {
    Value v;
    v._kind = Kind::NumberArray;
    v._isArray = true;
    v._typeName = std::move(typeName);
    v._components = components < 1 ? 1 : components;
    auto s = std::make_shared<Storage>();
    s->numbers = std::move(x);
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::stringArray(std::string typeName, std::vector<std::string> x, SourceLocation where) {
    Value v;
    v._kind = Kind::StringArray;
    v._isArray = true;
    v._typeName = std::move(typeName);
    auto s = std::make_shared<Storage>();
    s->strings = std::move(x);
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::assetArray(std::vector<AssetPath> x, SourceLocation where) {
    Value v;
    v._kind = Kind::AssetArray;
    v._isArray = true;
    v._typeName = "asset";
    auto s = std::make_shared<Storage>();
    s->strings.reserve(x.size());
    for (const AssetPath& a : x) s->strings.push_back(a.authored);
    s->assets = std::move(x);
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

Value Value::dictionary(Dictionary d, SourceLocation where) {
    Value v;
    v._kind = Kind::Dictionary;
    v._typeName = "dictionary";
    auto s = std::make_shared<Storage>();
    s->dict = std::move(d);
    v._data = std::move(s);
    v._where = std::move(where);
    return v;
}

std::optional<bool> Value::getBool() const {
    if (_kind != Kind::Number) return std::nullopt;
    if (_number == 0.0) return false;
    if (_number == 1.0 || _typeName == "bool") return true;
    return std::nullopt;
}

std::optional<std::int64_t> Value::getInt() const {
    if (_kind != Kind::Number || !std::isfinite(_number)) return std::nullopt;
    if (std::trunc(_number) != _number || std::fabs(_number) > 9.2e18) return std::nullopt;
    return static_cast<std::int64_t>(_number);
}

std::optional<double> Value::getDouble() const {
    if (_kind != Kind::Number) return std::nullopt;
    return _number;
}

std::optional<std::string> Value::getString() const {
    if (_kind != Kind::String) return std::nullopt;
    return _data->strings.front();
}

std::optional<AssetPath> Value::getAsset() const {
    if (_kind != Kind::Asset) return std::nullopt;
    return _data->assets.front();
}

std::optional<std::string> Value::getPath() const {
    if (_kind != Kind::Path) return std::nullopt;
    return _data->strings.front();
}

std::optional<std::vector<double>> Value::getTuple() const {
    if (_kind != Kind::Tuple) return std::nullopt;
    return _data->numbers;
}

const std::vector<double>* Value::numbers() const {
    return _kind == Kind::NumberArray ? &_data->numbers : nullptr;
}

std::size_t Value::size() const {
    switch (_kind) {
        case Kind::Empty:
        case Kind::None:
            return 0;
        case Kind::NumberArray:
            return _data->numbers.size() / static_cast<std::size_t>(_components);
        case Kind::StringArray:
        case Kind::AssetArray:
            return _data->strings.size();
        case Kind::Dictionary:
            return _data->dict.size();
        default:
            return 1;
    }
}

const std::vector<std::string>* Value::strings() const {
    return (_kind == Kind::StringArray || _kind == Kind::AssetArray) ? &_data->strings : nullptr;
}

const std::vector<AssetPath>* Value::assets() const {
    return _kind == Kind::AssetArray ? &_data->assets : nullptr;
}

const Dictionary* Value::dictionary() const {
    return _kind == Kind::Dictionary ? &_data->dict : nullptr;
}

const Value* Value::find(std::string_view key) const {
    if (_kind != Kind::Dictionary) return nullptr;
    auto it = _data->dict.find(key);
    return it == _data->dict.end() ? nullptr : &it->second;
}

bool Value::operator==(const Value& o) const {
    if (_kind != o._kind || _isArray != o._isArray || _components != o._components ||
        _typeName != o._typeName)
        return false;
    if (_kind == Kind::Number)
        return _number == o._number || (_number != _number && o._number != o._number);
    if (_data == o._data) return true;
    if (!_data || !o._data) return false;
    return _data->numbers == o._data->numbers && _data->strings == o._data->strings &&
           _data->assets == o._data->assets && _data->dict == o._data->dict;
}

std::string Value::toString() const {
    std::ostringstream os;
    auto numbersText = [&](const double* p, int n) {
        if (n > 1) os << '(';
        for (int i = 0; i < n; ++i) os << (i ? ", " : "") << p[i];
        if (n > 1) os << ')';
    };
    switch (_kind) {
        case Kind::Empty:
            return "<empty>";
        case Kind::None:
            return "None";
        case Kind::Number:
            numbersText(&_number, 1);
            break;
        case Kind::Tuple:
            numbersText(_data->numbers.data(), static_cast<int>(_data->numbers.size()));
            break;
        case Kind::String:
            os << '"' << _data->strings.front() << '"';
            break;
        case Kind::Asset:
            os << '@' << _data->strings.front() << '@';
            break;
        case Kind::Path:
            os << '<' << _data->strings.front() << '>';
            break;
        case Kind::NumberArray: {
            os << '[';
            std::size_t n = size();
            for (std::size_t i = 0; i < n && i < 8; ++i) {
                if (i) os << ", ";
                numbersText(_data->numbers.data() + i * _components, _components);
            }
            if (n > 8) os << ", ... (" << n << " elements)";
            os << ']';
            break;
        }
        case Kind::StringArray:
        case Kind::AssetArray: {
            os << '[';
            for (std::size_t i = 0; i < _data->strings.size() && i < 8; ++i)
                os << (i ? ", " : "") << '"' << _data->strings[i] << '"';
            if (_data->strings.size() > 8) os << ", ...";
            os << ']';
            break;
        }
        case Kind::Dictionary: {
            os << '{';
            bool first = true;
            for (const auto& [k, v] : _data->dict) {
                os << (first ? " " : ", ") << k << " = " << v.toString();
                first = false;
            }
            os << " }";
            break;
        }
    }
    return os.str();
}

}  // namespace principled::usd
