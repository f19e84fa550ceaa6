/* SPDX-License-Identifier: Apache-2.0 */
/* A test library that is not a plugin: it exports no entry point. */
__attribute__((visibility("default"))) int notAPlugin(void) {
    return 42;
}
