#pragma once
/// The one way Atelier reports errors, from the engine to the command line: a Result<T> is a
/// value or an Error naming the file, the place in it (JSON pointer, line, panel or seam) and
/// what is wrong (`shirt.json: /panels/3/edges/2: curvature must be finite`), with the further
/// problems found in the same pass. Libraries return these; they never print or exit.

#include <cassert>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace atelier {

/// What went wrong while reading or writing a file.
struct Error {
    std::string file;    ///< the file as the caller named it (may be empty)
    std::string where;   ///< JSON pointer (`/cloths/0/material`) or `line 12`; may be empty
    std::string message; ///< what is wrong, lower case, no trailing period
    std::vector<Error> more = {}; ///< further problems found in the same pass (each complete)

    /// `file: where: message`, leaving out the empty parts; one line per further problem.
    std::string toString() const {
        std::string s;
        for (const std::string* part : {&file, &where, &message}) {
            if (part->empty()) {
                continue;
            }
            if (!s.empty()) {
                s += ": ";
            }
            s += *part;
        }
        for (const Error& e : more) {
            s += '\n';
            s += e.toString();
        }
        return s;
    }
};

/// Either a value of type T or an Error. Check `ok()` before `value()`.
template <class T> class Result {
  public:
    Result(T value) : m_data(std::in_place_index<0>, std::move(value)) {}     // NOLINT: implicit
    Result(Error error) : m_data(std::in_place_index<1>, std::move(error)) {} // NOLINT: implicit

    bool ok() const { return m_data.index() == 0; }
    explicit operator bool() const { return ok(); }

    const T& value() const& {
        assert(ok());
        return std::get<0>(m_data);
    }
    T& value() & {
        assert(ok());
        return std::get<0>(m_data);
    }
    T&& value() && {
        assert(ok());
        return std::get<0>(std::move(m_data));
    }
    const Error& error() const {
        assert(!ok());
        return std::get<1>(m_data);
    }

  private:
    std::variant<T, Error> m_data;
};

/// Success without a value, or an Error.
template <> class Result<void> {
  public:
    Result() = default;
    Result(Error error) : m_error(std::move(error)), m_ok(false) {} // NOLINT: implicit

    bool ok() const { return m_ok; }
    explicit operator bool() const { return ok(); }
    const Error& error() const {
        assert(!ok());
        return m_error;
    }

  private:
    Error m_error;
    bool m_ok = true;
};

} // namespace atelier
