% test_drink_matches_cli: nrsfm_demo (nrsfm_reconstruct(W, 12) on drink,
% then e3D) gives the model that `nrsfm reconstruct --input drink.mat --K 12`
% writes, to 1e-12 in every array, and the e3D that the tool computes with
% --truth. Exit code 77 (skipped) without ../shared/datasets, or 1 (failed)
% when NRSFM_REQUIRE_SHARED=1 (as in CI; tests/test_util.h). Run by ctest
% (matlab/CMakeLists.txt) with NRSFM_CLI naming the tool.
shared = getenv('NRSFM_SHARED_DIR');
if isempty(shared)
  shared = getenv('NRSFM_DEFAULT_SHARED_DIR');
end
drink = fullfile(shared, 'datasets', 'drink.mat');
if isempty(shared) || ~exist(drink, 'file')
  if strcmp(getenv('NRSFM_REQUIRE_SHARED'), '1')
    fprintf(2, '%s not present and NRSFM_REQUIRE_SHARED=1: failed\n', drink);
    exit(1);
  end
  fprintf('%s not present: skipped\n', drink);
  exit(77);
end
cli = getenv('NRSFM_CLI');
out = [tempname() '_drink'];
command = sprintf('"%s" reconstruct --input "%s" --K 12 --output "%s" --truth "%s" --quiet', ...
                  cli, drink, out, drink);
[status, text] = system(command);
assert(status == 0, sprintf('%s failed: %s', command, text));

[e, model, info] = nrsfm_demo(drink);
F = size(model.weights, 1);
P = size(model.basis, 2);
K = size(model.basis, 3);
csv = @(name) dlmread(fullfile(out, name), ',', 1, 0);
R = csv('rotations.csv');          % frame, camera, r11 r12 r13 r21 ... r33
T = csv('translations.csv');       % frame, camera, tx, ty, scale
L = csv('weights.csv');            % frame, l1 .. lK
B = csv('basis.csv');              % k, point, x, y, z
X = csv('points_camera.csv');      % frame, camera, point, x, y, z
O = csv('points_object.csv');      % frame, point, x, y, z
assert(size(R, 1) == F && size(L, 2) == K + 1 && size(B, 1) == K * P, 'sizes of the files');
difference = 0;
for t = 1:F
  difference = max(difference, max(max(abs(reshape(R(t, 3:11), 3, 3)' - model.rotations(:, :, t)))));
  difference = max(difference, max(abs(T(t, 3:4)' - model.translations(:, t))));
  difference = max(difference, abs(T(t, 5) - model.scales(t)));
end
difference = max(difference, max(max(abs(L(:, 2:end) - model.weights))));
% Rows frame-major then point (points_camera also camera): the MATLAB
% arrays' columns in order.
difference = max(difference, max(max(abs(B(:, 3:5)' - reshape(model.basis, 3, [])))));
difference = max(difference, max(max(abs(X(:, 4:6)' - reshape(model.points_camera, 3, [])))));
difference = max(difference, max(max(abs(O(:, 3:5)' - reshape(model.points_object, 3, [])))));
result = jsondecode(fileread(fullfile(out, 'result.json')));
fprintf('drink: largest difference from the tool %.3g; e3D %.6f (the tool: %.6f)\n', ...
        difference, e, result.metrics.e3d);
assert(difference <= 1e-12, sprintf('the model differs from the tool''s by %g', difference));
assert(abs(e - result.metrics.e3d) < 1e-9, 'nrsfm_e3d differs from the tool''s e3D');
assert(abs(info.reprojection_rms - result.reprojection_rms) <= 1e-12, 'reprojection RMS');
if exist('OCTAVE_VERSION', 'builtin')
  confirm_recursive_rmdir(false);
end
rmdir(out, 's');
fprintf('test_drink_matches_cli: all checks passed\n');
