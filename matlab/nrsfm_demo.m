function [e, model, info] = nrsfm_demo(drink)
% NRSFM_DEMO  The field's usual loop with nrsfm: load drink.mat,
% reconstruct with K = 12, score with e3D against the world-frame truth S.
%   [e, model, info] = nrsfm_demo(drink) takes the path of drink.mat (by
%   default ../shared/datasets/drink.mat from the repository's root). Needs
%   nrsfm_reconstruct (the MEX file: build/matlab) and nrsfm_e3d (matlab/)
%   on the path. Prints and returns e3D; about 10 s.
if nargin < 1
  drink = fullfile('..', 'shared', 'datasets', 'drink.mat');
end
data = load(drink);                       % W (2F x P), S (3F x P, world frame)
[model, info] = nrsfm_reconstruct(data.W, 12);
% The object-frame shapes S_t (3 x P x F) as 3F x P, rows x_t, y_t, z_t.
P = size(data.W, 2);
S_est = reshape(permute(model.points_object, [1 3 2]), [], P);
e = nrsfm_e3d(data.S, S_est);
fprintf('drink, K = 12: e3D %.4f (object frame), reprojection RMS %.3g, %d LM iterations\n', ...
        e, info.reprojection_rms, info.stages(2).iterations);
end
