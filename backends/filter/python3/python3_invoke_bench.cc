// SPDX-License-Identifier: LGPL-2.1-only
// Placeholder; replaced below.
int main() {
  return 0;
}
