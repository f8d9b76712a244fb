#!/usr/bin/env python3
"""Summarize JUnit XML test results (gtest, rostest, catkin MISSING-RESULT files).

    summarize_tests.py RESULTS_DIR

Counts test cases in every *.xml below RESULTS_DIR, prints the failing ones, and prints as the
last line exactly "N passed, N failed". Exit status 1 if any test case failed or none ran.

rostest writes rostest-<file>.xml with one test case per test node ("test<name>") and the node
writes its own test cases to rosunit-<name>.xml: a node's cases are counted from its rosunit
file; the rostest case is counted only when that file is missing (node crashed, timed out), or
as one extra failure when rostest failed although the node's own cases all passed.
A result file that cannot be parsed counts as one failed test case.
"""
import os
import re
import sys
import xml.etree.ElementTree as ET


class Summary:
    def __init__(self, results_dir):
        self.results_dir = results_dir
        self.passed = 0
        self.failed = 0
        self.skipped = 0
        self.failures = []

    def fail(self, what, message=''):
        self.failed += 1
        self.failures.append(what + (': ' + message if message else ''))

    def parse(self, path):
        try:
            return ET.parse(path).getroot()
        except (ET.ParseError, OSError) as e:
            self.fail(os.path.relpath(path, self.results_dir), 'unreadable result file (%s)' % e)
            return None

    @staticmethod
    def problem(case):
        bad = case.find('failure')
        if bad is None:
            bad = case.find('error')
        if bad is None:
            return None
        text = bad.get('message') or bad.text or ''
        lines = [line.strip() for line in text.splitlines() if line.strip()]
        if not lines:
            return 'failed'
        # gtest: "file:line" then the expectation; otherwise the first line says it.
        count = 3 if re.match(r'^\S+:\d+$', lines[0]) else 1
        return ' | '.join(lines[:count])

    def count_case(self, case, rel):
        name = '%s.%s (%s)' % (case.get('classname', ''), case.get('name', ''), rel)
        message = self.problem(case)
        if message is not None:
            self.fail(name, message)
        elif case.find('skipped') is not None or case.get('status') == 'notrun':
            self.skipped += 1
        else:
            self.passed += 1

    def count_file(self, path):
        """Counts all test cases of a file; returns the number of failures found in it."""
        root = self.parse(path)
        if root is None:
            return 1
        before = self.failed
        rel = os.path.relpath(path, self.results_dir)
        for case in root.iter('testcase'):
            self.count_case(case, rel)
        return self.failed - before

    def count_dir(self, dirpath, names):
        rosunit = {n[len('rosunit-'):-len('.xml')]: n for n in names if n.startswith('rosunit-')}
        used = set()
        for name in sorted(names):
            if name.startswith('rosunit-'):
                continue
            path = os.path.join(dirpath, name)
            if not name.startswith('rostest-'):
                self.count_file(path)
                continue
            root = self.parse(path)
            if root is None:
                continue
            rel = os.path.relpath(path, self.results_dir)
            for case in root.iter('testcase'):
                node = case.get('name', '')[len('test'):]
                own = rosunit.get(node)
                if case.get('classname') == 'rostest.runner.RosTest' and own and own not in used:
                    used.add(own)
                    node_failures = self.count_file(os.path.join(dirpath, own))
                    message = self.problem(case)
                    if message is not None and node_failures == 0:
                        self.fail('%s (%s)' % (case.get('name'), rel), message)
                else:
                    self.count_case(case, rel)
        for node, name in sorted(rosunit.items()):
            if name not in used:
                self.count_file(os.path.join(dirpath, name))


def main(argv):
    if len(argv) != 2:
        print('usage: summarize_tests.py RESULTS_DIR', file=sys.stderr)
        return 2
    summary = Summary(argv[1])
    for dirpath, _, filenames in sorted(os.walk(argv[1])):
        names = [n for n in filenames if n.endswith('.xml')]
        if names:
            summary.count_dir(dirpath, names)
    for line in summary.failures:
        print('FAILED: ' + line)
    if summary.skipped:
        print('%d skipped' % summary.skipped)
    total = summary.passed + summary.failed
    if total == 0:
        print('no test ran: no test cases in %s' % argv[1])
    print('%d passed, %d failed' % (summary.passed, summary.failed))
    return 1 if summary.failed or total == 0 else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
