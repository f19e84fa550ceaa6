// SPDX-License-Identifier: Apache-2.0
// Sdf list operations (references, inherits, apiSchemas, relationship targets, connections):
// an explicit list, or add / prepend / append / delete / reorder edits applied on top of the
// weaker opinions' result.
#pragma once

#include <algorithm>
#include <vector>

namespace principled::usd {

enum class ListOpKind { Explicit, Add, Prepend, Append, Delete, Reorder };

template <class T>
struct ListOp {
    bool isExplicit = false;
    std::vector<T> explicitItems, added, prepended, appended, deleted, ordered;

    bool empty() const {
        return !isExplicit && added.empty() && prepended.empty() && appended.empty() &&
               deleted.empty() && ordered.empty();
    }

    /// Records one authored statement (a later statement of the same kind replaces it).
    void set(ListOpKind kind, std::vector<T> items) {
        switch (kind) {
            case ListOpKind::Explicit:
                *this = ListOp{};
                isExplicit = true;
                explicitItems = std::move(items);
                break;
            case ListOpKind::Add:
                added = std::move(items);
                break;
            case ListOpKind::Prepend:
                prepended = std::move(items);
                break;
            case ListOpKind::Append:
                appended = std::move(items);
                break;
            case ListOpKind::Delete:
                deleted = std::move(items);
                break;
            case ListOpKind::Reorder:
                ordered = std::move(items);
                break;
        }
    }

    /// Applies this (stronger) opinion on top of `list`, the result of the weaker ones, in Sdf's
    /// order: delete, add, prepend, append, reorder.
    void applyTo(std::vector<T>& list) const {
        auto remove = [&list](const T& item) {
            list.erase(std::remove(list.begin(), list.end(), item), list.end());
        };
        auto contains = [&list](const T& item) {
            return std::find(list.begin(), list.end(), item) != list.end();
        };
        if (isExplicit) {
            list.clear();
            for (const T& item : explicitItems)
                if (!contains(item)) list.push_back(item);
            return;
        }
        for (const T& item : deleted) remove(item);
        for (const T& item : added)
            if (!contains(item)) list.push_back(item);
        if (!prepended.empty()) {
            std::vector<T> front;
            for (const T& item : prepended) {
                if (std::find(front.begin(), front.end(), item) != front.end()) continue;
                remove(item);
                front.push_back(item);
            }
            list.insert(list.begin(), front.begin(), front.end());
        }
        for (const T& item : appended) {
            remove(item);
            list.push_back(item);
        }
        if (!ordered.empty()) reorder(list);
    }

private:
    /// Sdf reorder: each named item moves, in the given order, together with the unnamed items
    /// that follow it; items before every named one stay in front.
    void reorder(std::vector<T>& list) const {
        std::vector<T> order;
        for (const T& item : ordered)
            if (std::find(order.begin(), order.end(), item) == order.end()) order.push_back(item);
        auto named = [&order](const T& item) {
            return std::find(order.begin(), order.end(), item) != order.end();
        };
        std::vector<bool> taken(list.size(), false);
        std::vector<T> runs;
        for (const T& item : order) {
            auto it = std::find(list.begin(), list.end(), item);
            if (it == list.end()) continue;
            std::size_t i = static_cast<std::size_t>(it - list.begin());
            do {
                runs.push_back(list[i]);
                taken[i] = true;
                ++i;
            } while (i < list.size() && !named(list[i]));
        }
        std::vector<T> result;
        result.reserve(list.size());
        for (std::size_t i = 0; i < list.size(); ++i)
            if (!taken[i]) result.push_back(list[i]);
        result.insert(result.end(), runs.begin(), runs.end());
        list = std::move(result);
    }
};

}  // namespace principled::usd
