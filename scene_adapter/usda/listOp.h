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

    /// Applies this (stronger) opinion on top of `list`, the result of the weaker ones.
    /// Reorder moves the named items, in that order, to the front (a simplification of Sdf's
    /// relative reorder).
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
        if (!ordered.empty()) {
            std::vector<T> front;
            for (const T& item : ordered) {
                if (!contains(item)) continue;
                remove(item);
                front.push_back(item);
            }
            list.insert(list.begin(), front.begin(), front.end());
        }
    }
};

}  // namespace principled::usd
