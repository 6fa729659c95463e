#pragma once
/// What the document's edit functions share (patterns/document_edit.cpp and
/// patterns/document_marks.cpp): recording an edit's before and after states, and the
/// helpers several edits use. Not for use outside patterns/.

#include "patterns/document_edit.h"

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace atelier::patterns::detail {

inline Error editError(const std::string& where, std::string message) {
    return Error{"", where, std::move(message)};
}

inline std::string panelWhere(PanelId id) {
    return "panel #" + std::to_string(id.value);
}

template <class T>
std::optional<std::size_t> indexOfId(const std::vector<T>& items, decltype(T::id) id) {
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (items[i].id == id) {
            return i;
        }
    }
    return std::nullopt;
}

/// The changes of the objects `touched` (ids, before-states taken now) and of every object
/// added meanwhile, once `mutate` has run.
template <class T> class Snapshot {
  public:
    Snapshot(const std::vector<T>& items, const std::vector<decltype(T::id)>& touched) {
        for (const T& x : items) {
            m_existing.insert(x.id);
        }
        for (const auto id : touched) {
            if (m_recorded.count(id) != 0) {
                continue;
            }
            m_recorded.insert(id);
            Change<T> c;
            if (const auto i = indexOfId(items, id)) {
                c.before = items[*i];
                c.beforeIndex = *i;
            }
            m_changes.push_back(std::move(c));
            m_ids.push_back(id);
        }
    }

    std::vector<Change<T>> finish(const std::vector<T>& items) && {
        for (std::size_t k = 0; k < m_changes.size(); ++k) {
            if (const auto i = indexOfId(items, m_ids[k])) {
                m_changes[k].after = items[*i];
                m_changes[k].afterIndex = *i;
            }
        }
        for (std::size_t i = 0; i < items.size(); ++i) {
            if (m_existing.count(items[i].id) == 0 && m_recorded.count(items[i].id) == 0) {
                m_changes.push_back({std::nullopt, items[i], 0, i});
            }
        }
        // Dropping untouched entries keeps the edit small (a declared object left alone).
        std::vector<Change<T>> out;
        for (Change<T>& c : m_changes) {
            if (c.before || c.after) {
                out.push_back(std::move(c));
            }
        }
        return out;
    }

  private:
    std::set<decltype(T::id)> m_existing;
    std::set<decltype(T::id)> m_recorded;
    std::vector<decltype(T::id)> m_ids;
    std::vector<Change<T>> m_changes;
};

/// Runs `mutate` on the document, recording the panels and seams it declares it touches and
/// every one it adds. On failure the document is restored and the error returned.
template <class F>
Result<Edit> record(GarmentDocument& d, std::string description, const std::vector<PanelId>& panels,
                    const std::vector<SeamId>& seams, F&& mutate) {
    Snapshot<doc::Panel> panelSnapshot(d.panels, panels);
    Snapshot<doc::Seam> seamSnapshot(d.seams, seams);
    Edit edit;
    edit.description = std::move(description);
    edit.nextIdBefore = d.nextId;
    const Result<std::uint32_t> result = mutate(d);
    edit.panels = std::move(panelSnapshot).finish(d.panels);
    edit.seams = std::move(seamSnapshot).finish(d.seams);
    edit.nextIdAfter = d.nextId;
    if (!result.ok()) {
        undo(d, edit);
        return result.error();
    }
    edit.created = result.value();
    return edit;
}

/// Seams with a range on `panel` (on `edge` when given).
std::vector<SeamId> seamsOn(const GarmentDocument& d, PanelId panel, EdgeId edge = {});

/// Whether `e` is a leg of one of the panel's darts.
bool isDartLeg(const doc::Panel& p, EdgeId e);

/// Inserts a point on an outline or hole edge at t ∈ (0, 1) (as splitEdge, without recording);
/// its id's value, or an error.
Result<std::uint32_t> splitEdgeIn(GarmentDocument& d, PanelId panelId, EdgeId edgeId, double t);

} // namespace atelier::patterns::detail
